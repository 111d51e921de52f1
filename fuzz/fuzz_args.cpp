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
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cli/args.hpp"
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
