// Fuzz target: the command-line parser every subcommand uses (cli/args.hpp).
//
// Input layout: u8 n, then n option specs of 2 bytes each (a name from kNames, which also holds
// the odd cases: a name that is a prefix of another, one with '=', an empty one; a repeated name is
// skipped, as no command has one; flags bit 0 takes a value, 1 repeatable, 2-3 a short name), then
// the words, separated by NUL bytes. The typed getters' ranges come from the words themselves.
//
// What must hold: Args either parses or throws UsageError (a one-line message); after a parse,
// every value and positional is one of the words (options in order of appearance), a
// non-repeatable option has at most one value, a flag's value is "1", and get_int / get_double /
// parse_int / parse_double return a number inside the requested range or throw UsageError;
// split_commas drops exactly the empty items.
//
// The same words also fill DetectorOptions (detect/detector.hpp), the options they become in
// `tagbench detect`: the k-th word that is a whole number (from_chars: nan, inf, huge values
// included) sets field k mod kFields.size() of the table below (a camera or distortion field
// brings a camera with a valid tag size unless the words set those too). What must hold:
// validate() either passes, and then a Detector is built from the options without a throw, or
// throws std::invalid_argument with one line "FIELD = VALUE: ..." whose FIELD is one of the
// table's names and one the words set (or, for a rule between two fields, the message names the
// other one the words set).
#include <array>
#include <charconv>
#include <climits>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "detect/detector.hpp"
#include "fuzz_util.hpp"

namespace {

const std::array<std::string, 16> kNames = {"family", "max-hamming", "camera", "tag-size", "half-res", "format",
                                            "draw",   "threads",     "out",    "o",        "out-dir",  "a=b",
                                            "",       "fam",         "-",      "help"};
const std::array<std::string, 4> kShort = {"", "o", "n", "-"};

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

void check_usage_error(const tagbench::cli::UsageError& e) {
  // Option names and values come from the words, which may hold newlines: only emptiness is ours.
  FUZZ_CHECK(std::string(e.what()).size() > 0, "empty usage error");
}

// Conversions without undefined behaviour for NaN and out-of-range values.
long long to_ll(double v, long long lo, long long hi) {
  if (!(v >= static_cast<double>(lo))) return lo;  // NaN too
  if (!(v <= static_cast<double>(hi))) return hi;
  return static_cast<long long>(v);
}
int to_int(double v) { return static_cast<int>(to_ll(v, INT_MIN, INT_MAX)); }
float to_float(double v) {
  if (std::isnan(v)) return NAN;
  if (v > FLT_MAX) return INFINITY;
  if (v < -FLT_MAX) return -INFINITY;
  return static_cast<float>(v);
}

using tagbench::DetectorOptions;
tagbench::CameraIntrinsics& cam(DetectorOptions& o) {
  if (!o.camera) o.camera = tagbench::CameraIntrinsics{500, 500, 320, 240};
  return *o.camera;
}
double& dist(DetectorOptions& o, std::size_t i) {
  cam(o);
  if (!o.distortion) o.distortion = std::array<double, 5>{};
  return (*o.distortion)[i];
}

struct Field {
  const char* name;  // as validate() names it
  std::function<void(DetectorOptions&, double)> set;
};
const std::vector<Field> kFields = {
    {"max_hamming", [](DetectorOptions& o, double v) { o.max_hamming = to_int(v); }},
    {"min_decision_margin", [](DetectorOptions& o, double v) { o.min_decision_margin = v; }},
    {"seg_sigma", [](DetectorOptions& o, double v) { o.seg_sigma = v; }},
    {"decode_sigma", [](DetectorOptions& o, double v) { o.decode_sigma = v; }},
    {"segmentation.min_mag", [](DetectorOptions& o, double v) { o.segmentation.min_mag = to_float(v); }},
    {"segmentation.max_edge_cost", [](DetectorOptions& o, double v) { o.segmentation.max_edge_cost = v; }},
    {"segmentation.weight_scale", [](DetectorOptions& o, double v) { o.segmentation.weight_scale = to_int(v); }},
    {"segmentation.k_theta", [](DetectorOptions& o, double v) { o.segmentation.k_theta = v; }},
    {"segmentation.k_mag", [](DetectorOptions& o, double v) { o.segmentation.k_mag = v; }},
    {"segmentation.min_cluster_size", [](DetectorOptions& o, double v) { o.segmentation.min_cluster_size = to_int(v); }},
    {"line_fit.min_length", [](DetectorOptions& o, double v) { o.line_fit.min_length = v; }},
    {"quad_search.close_enough",
     [](DetectorOptions& o, double v) { o.quad_search.close_enough = static_cast<tagbench::CloseEnoughRule>(to_int(v)); }},
    {"quad_search.min_tag_size", [](DetectorOptions& o, double v) { o.quad_search.min_tag_size = v; }},
    {"quad_search.max_aspect", [](DetectorOptions& o, double v) { o.quad_search.max_aspect = v; }},
    {"quad_search.winding_min", [](DetectorOptions& o, double v) { o.quad_search.winding_min = v; }},
    {"quad_search.winding_max", [](DetectorOptions& o, double v) { o.quad_search.winding_max = v; }},
    {"quad_search.grid_cell", [](DetectorOptions& o, double v) { o.quad_search.grid_cell = v; }},
    {"quad_search.max_quads",
     [](DetectorOptions& o, double v) { o.quad_search.max_quads = static_cast<std::size_t>(to_ll(v, 0, LLONG_MAX)); }},
    {"payload.min_contrast", [](DetectorOptions& o, double v) { o.payload.min_contrast = v; }},
    {"camera.fx", [](DetectorOptions& o, double v) { cam(o).fx = v; }},
    {"camera.fy", [](DetectorOptions& o, double v) { cam(o).fy = v; }},
    {"camera.cx", [](DetectorOptions& o, double v) { cam(o).cx = v; }},
    {"camera.cy", [](DetectorOptions& o, double v) { cam(o).cy = v; }},
    {"tag_size", [](DetectorOptions& o, double v) { o.tag_size = v; }},
    {"distortion.k1", [](DetectorOptions& o, double v) { dist(o, 0) = v; }},
    {"distortion.k2", [](DetectorOptions& o, double v) { dist(o, 1) = v; }},
    {"distortion.p1", [](DetectorOptions& o, double v) { dist(o, 2) = v; }},
    {"distortion.p2", [](DetectorOptions& o, double v) { dist(o, 3) = v; }},
    {"distortion.k3", [](DetectorOptions& o, double v) { dist(o, 4) = v; }},
    {"max_pixels", [](DetectorOptions& o, double v) { o.max_pixels = to_ll(v, LLONG_MIN, LLONG_MAX); }},
};

void check_detector_options(const std::vector<std::string>& words) {
  DetectorOptions o;
  std::vector<bool> set(kFields.size(), false);
  std::size_t k = 0;
  for (const auto& w : words) {
    double v = 0;
    const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
    if (w.empty() || r.ec != std::errc() || r.ptr != w.data() + w.size()) continue;
    const std::size_t i = k++ % kFields.size();
    kFields[i].set(o, v);
    set[i] = true;
  }
  const std::size_t tag_size = 23;  // kFields' index of tag_size
  FUZZ_CHECK(std::string(kFields[tag_size].name) == "tag_size", "the tag_size index is stale");
  if (o.camera && !set[tag_size]) o.tag_size = 0.1;  // a camera the words brought needs a tag size
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    FUZZ_CHECK(!m.empty() && m.find('\n') == std::string::npos, "validate()'s message is not one line: " + m);
    bool known = false, named = false, mentions_set = false;
    for (std::size_t i = 0; i < kFields.size(); ++i) {
      const bool starts = m.rfind(std::string(kFields[i].name) + " = ", 0) == 0;
      known = known || starts;
      named = named || (starts && set[i]);
      mentions_set = mentions_set || (set[i] && m.find(kFields[i].name) != std::string::npos);
    }
    FUZZ_CHECK(known, "validate()'s message does not start with 'FIELD = ': " + m);
    FUZZ_CHECK(named || mentions_set, "validate() refused a field the input did not set: " + m);
    return;
  }
  try {
    const tagbench::Detector det(o);
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, std::string("validate() passed but the Detector refused the options: ") + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using tagbench::cli::Args;
  using tagbench::cli::OptionSpec;
  using tagbench::cli::UsageError;

  fuzz::Reader in(data, size);
  std::vector<OptionSpec> specs;
  const int n = in.u8() % 9;
  for (int i = 0; i < n; ++i) {
    const std::uint8_t name = in.u8(), flags = in.u8();
    const std::string& nm = kNames[name % kNames.size()];
    // Two specs of one name would be a bug of the command's table, not of its input: one each.
    bool dup = false;
    for (const auto& s : specs) dup = dup || s.name == nm;
    if (!dup) specs.emplace_back(nm, (flags & 1) != 0, (flags & 2) != 0, kShort[(flags >> 2) & 3]);
  }
  std::vector<std::string> words;
  {
    const std::string rest = in.rest();
    std::size_t start = 0;
    while (start <= rest.size() && !rest.empty()) {
      const auto nul = rest.find('\0', start);
      words.push_back(rest.substr(start, nul == std::string::npos ? std::string::npos : nul - start));
      if (nul == std::string::npos) break;
      start = nul + 1;
    }
  }

  check_detector_options(words);

  std::optional<Args> args;
  try {
    args.emplace(words, specs);
  } catch (const UsageError& e) {
    check_usage_error(e);
    return 0;
  }

  // Positionals: a subsequence of the words, in order.
  {
    std::size_t w = 0;
    for (const auto& p : args->positionals()) {
      while (w < words.size() && words[w] != p) ++w;
      FUZZ_CHECK(w < words.size(), "positional '" + p + "' is not one of the words (or out of order)");
      ++w;
    }
  }
  for (const auto& spec : specs) {
    const auto values = args->all(spec.name);
    if (!spec.repeatable) FUZZ_CHECK(values.size() <= 1, "--" + spec.name + " has several values");
    FUZZ_CHECK(args->has(spec.name) == !values.empty(), "has() disagrees with all()");
    for (const auto& v : values) {
      if (!spec.takes_value) {
        FUZZ_CHECK(v == "1", "flag --" + spec.name + " has the value '" + v + "'");
        continue;
      }
      bool from_words = false;
      for (const auto& w : words) from_words = from_words || w == v || w.ends_with("=" + v);
      FUZZ_CHECK(from_words, "value '" + v + "' of --" + spec.name + " is not in the words");
    }
    if (values.empty()) continue;
    FUZZ_CHECK(args->get(spec.name) == values.back(), "get() is not the last value");

    // Typed getters with ranges taken from the value's length, so both sides of a bound are hit.
    const long long lo = -static_cast<long long>(values.back().size()) * 7, hi = static_cast<long long>(words.size());
    try {
      const long long v = args->get_int(spec.name, 0, lo, hi);
      FUZZ_CHECK(v >= lo && v <= hi, "get_int out of range");
      FUZZ_CHECK(tagbench::cli::parse_int("--x", std::to_string(v), lo, hi) == v, "parse_int does not round-trip");
    } catch (const UsageError& e) {
      FUZZ_CHECK(one_line(e.what()) || values.back().find('\n') != std::string::npos, e.what());
    }
    try {
      const double v = args->get_double(spec.name, 0.0, static_cast<double>(lo), static_cast<double>(hi));
      FUZZ_CHECK(std::isfinite(v) && v >= static_cast<double>(lo) && v <= static_cast<double>(hi),
                 "get_double out of range");
    } catch (const UsageError& e) {
      check_usage_error(e);
    }
    std::size_t non_empty = 0, start = 0;
    const std::string& text = values.back();
    while (start <= text.size()) {
      const auto comma = text.find(',', start);
      const auto end = comma == std::string::npos ? text.size() : comma;
      if (end > start) ++non_empty;
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    const auto items = tagbench::cli::split_commas(text);
    FUZZ_CHECK(items.size() == non_empty, "split_commas kept or lost an item");
    for (const auto& item : items)
      FUZZ_CHECK(!item.empty() && item.find(',') == std::string::npos, "split_commas item '" + item + "'");
  }
  return 0;
}
