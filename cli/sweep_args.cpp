#include "cli/sweep_args.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace tagbench::cli {

using namespace tagbench::bench;

std::vector<OptionSpec> sweep_option_specs() {
  return {{"trials"}, {"tag-size"}, {"seed"}, {"family"}, {"scene"}, {"distance"}, {"angles"}, {"distances"}, {"conditions"},
          {"frames"}, {"distance-range"}, {"phi-max"}, {"lens"}, {"defocus-max"}, {"noise-max"}, {"bins"}};
}

namespace {

std::vector<double> number_list(const std::string& option, const std::string& s) {
  std::vector<double> v;
  for (const auto& item : split_items(option, s)) v.push_back(parse_double(option, item, -1e300, 1e300));
  return v;
}

}  // namespace

SweepSettings parse_sweep_settings(const std::string& name, const Args& a, const std::vector<std::string>& detectors) {
  SweepSettings base;
  base.detectors = detectors;
  return parse_sweep_settings(name, a, std::move(base));
}

SweepSettings parse_sweep_settings(const std::string& name, const Args& a, SweepSettings s) {
  try {
    s.experiment = parse_experiment(name);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const bool sixdof = s.experiment == Experiment::kSixdof;
  if (sixdof) {
    if (a.has("trials")) throw UsageError("--trials: the sixdof sweep takes --frames N");
    s.trials = static_cast<int>(a.get_int("frames", 100, -1000000000, 1000000000));
    SixdofSettings& x = s.sixdof;
    if (a.has("distance-range")) {
      const std::vector<double> r = number_list("--distance-range", *a.get("distance-range"));
      if (r.size() != 2) throw UsageError("--distance-range: expected A,B (metres), got '" + *a.get("distance-range") + "'");
      x.distance_min = r[0];
      x.distance_max = r[1];
    }
    if (a.has("lens")) {
      const std::vector<double> k = number_list("--lens", *a.get("lens"));
      if (k.size() != 5) throw UsageError("--lens: expected k1,k2,p1,p2,k3 (OpenCV's model), got '" + *a.get("lens") + "'");
      for (std::size_t i = 0; i < 5; ++i) x.distortion[i] = k[i];
    }
    x.phi_max_deg = a.get_double("phi-max", x.phi_max_deg, -1e300, 1e300);
    x.defocus_max_px = a.get_double("defocus-max", x.defocus_max_px, -1e300, 1e300);
    x.noise_max = a.get_double("noise-max", x.noise_max, -1e300, 1e300);
    x.bins = static_cast<int>(a.get_int("bins", x.bins, -1000000000, 1000000000));
  } else {
    for (const char* o : {"frames", "distance-range", "phi-max", "lens", "defocus-max", "noise-max", "bins"})
      if (a.has(o)) throw UsageError(std::string("--") + o + " belongs to the sixdof sweep");
    s.trials = static_cast<int>(a.get_int("trials", 5, -1000000000, 1000000000));
  }
  if (a.has("tag-size")) s.tag_size = parse_double("--tag-size", *a.get("tag-size"), -1e300, 1e300);
  if (a.has("seed")) s.seed = static_cast<std::uint64_t>(parse_int("--seed", *a.get("seed"), 0, (1LL << 62)));
  if (a.has("family")) s.family = *a.get("family");
  if (a.has("distance")) {
    if (s.experiment == Experiment::kDistance) throw UsageError("--distance: the distance sweep takes --distances");
    if (sixdof) throw UsageError("--distance: the sixdof sweep takes --distance-range A,B");
    s.distance = parse_double("--distance", *a.get("distance"), -1e300, 1e300);
  }
  if (a.has("angles")) {
    if (s.experiment != Experiment::kAngle) throw UsageError("--angles belongs to the angle sweep");
    s.steps = number_list("--angles", *a.get("angles"));
  }
  if (a.has("distances")) {
    if (s.experiment != Experiment::kDistance) throw UsageError("--distances belongs to the distance sweep");
    s.steps = number_list("--distances", *a.get("distances"));
  }
  try {
    if (a.has("conditions")) {
      if (s.experiment != Experiment::kConditions) throw UsageError("--conditions belongs to the conditions sweep");
      for (const auto& c : split_items("--conditions", *a.get("conditions"))) s.conditions.push_back(parse_condition(c));
    }
    if (a.has("scene")) s.scene = parse_scene(*a.get("scene"));
    s = resolve_settings(s);
    plan_sweep(s);  // a tag that does not fit is refused before anything is rendered or written
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return s;
}

void parse_detector_list(const std::string& option, const std::string& list, double external_timeout,
                         SweepSettings& s) {
  parse_detector_list(option, list, external_timeout, s.detectors, s.external);
}

void parse_detector_list(const std::string& option, const std::string& list, double external_timeout,
                         std::vector<std::string>& detectors, std::vector<ExternalDetector>& external) {
  const auto& known = known_comparator_names();
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const bool starts_item = item.rfind("external:", 0) == 0 || std::find(known.begin(), known.end(), item) != known.end() || is_ours_variant(item);
    if (!items.empty() && items.back().rfind("external:", 0) == 0 && !starts_item) items.back() += "," + item;
    else items.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  for (const auto& item : items) {
    if (item.empty()) throw UsageError(option + ": empty item in '" + list + "'");
    if (item.rfind("external:", 0) == 0) {
      try {
        external.push_back(parse_external_detector(item.substr(9), external_timeout));
      } catch (const std::invalid_argument& e) {
        throw UsageError(option + ": " + e.what());
      }
      detectors.push_back(external.back().name);
    } else {
      detectors.push_back(item);
    }
  }
}

void check_out_folder(const std::string& option, const std::string& out_text) {
  const std::filesystem::path out = out_text;
  for (std::filesystem::path p = out; !p.empty(); p = p.parent_path()) {
    std::error_code ec;
    if (std::filesystem::exists(p, ec)) {
      if (!std::filesystem::is_directory(p, ec))
        throw UsageError(option + " " + out.string() + ": " + (p == out ? "" : p.string() + " is ") + "not a directory");
      break;
    }
    if (p == p.parent_path()) break;
  }
}

}  // namespace tagbench::cli
