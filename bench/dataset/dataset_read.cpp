// read_dataset: a truth.json back into the sweep's frames (dataset.hpp).
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "codes/families.hpp"
#include "dataset/dataset.hpp"
#include "tools/atomic_file.hpp"
#include "tools/json_read.hpp"

namespace tagbench::bench {

namespace {

Eigen::Matrix3d read_matrix(const JsonValue& v, const std::string& what) {
  const auto& rows = v.array(what);
  if (rows.size() != 3) throw JsonError(what + ": expected 3 rows");
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    const auto& r = rows[static_cast<std::size_t>(i)].array(what);
    if (r.size() != 3) throw JsonError(what + ": expected 3 numbers a row");
    for (int k = 0; k < 3; ++k) m(i, k) = r[static_cast<std::size_t>(k)].number(what);
  }
  return m;
}

std::vector<double> read_numbers(const JsonValue& v, std::size_t n, const std::string& what) {
  const auto& a = v.array(what);
  if (n && a.size() != n) throw JsonError(what + ": expected " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const auto& x : a) out.push_back(x.number(what));
  return out;
}

// A frame's file: a plain name inside the dataset folder (never a path out of it).
std::string read_file_name(const JsonValue& v, const std::string& what) {
  const std::string& s = v.string(what);
  if (s.empty() || s == "." || s == ".." || s.find('/') != std::string::npos || s.find('\0') != std::string::npos)
    throw JsonError(what + ": '" + s + "' is not a file name inside the dataset folder");
  return s;
}

DatasetFrame read_frame(const JsonValue& j, const Dataset& d) {
  std::string what = "frames[?]";
  DatasetFrame out;
  out.index = static_cast<std::size_t>(j.at("index", what).uint64(what + ": index"));
  what = "frame " + std::to_string(out.index);
  out.file = read_file_name(j.at("file", what), what + ": file");
  SweepFrame& f = out.frame;
  const std::string cond = j.at("condition", what).string(what + ": condition");
  f.condition = cond == "none" ? Condition::kNone : parse_condition(cond);
  f.step = j.at("step", what).number(what + ": step");
  f.trial = j.at("trial", what).integer(what + ": trial");
  f.seed = j.at("seed", what).uint64(what + ": seed");
  f.frame.family = j.at("family", what).string(what + ": family");
  f.frame.id = j.at("id", what).integer(what + ": id");
  f.frame.tag_size = j.at("tag_size_m", what).number(what + ": tag_size_m");
  f.frame.pose.R = read_matrix(j.at("R", what), what + ": R");
  // Written at full precision by the export: a rotation to far better than this.
  const double off = rotation_defect(f.frame.pose.R);
  if (!(off <= 1e-6)) throw JsonError(what + ": R: not a rotation (R^T R differs from I by " + std::to_string(off) + ")");
  const auto t = read_numbers(j.at("t", what), 3, what + ": t");
  f.frame.pose.t = Eigen::Vector3d(t[0], t[1], t[2]);
  f.truth.pose = f.frame.pose;
  const auto& corners = j.at("corners", what).array(what + ": corners");
  if (corners.size() != 4) throw JsonError(what + ": corners: expected 4 points");
  for (std::size_t k = 0; k < 4; ++k) {
    const auto p = read_numbers(corners[k], 2, what + ": corners");
    f.truth.corners[k] = Eigen::Vector2d(p[0], p[1]);
  }
  f.truth.black_square_px = j.at("black_square_px", what).number(what + ": black_square_px");
  if (const JsonValue* dist = j.find("distortion"); dist && !dist->is_null()) {
    const auto k = read_numbers(*dist, 5, what + ": distortion");
    out.distortion = std::array<double, 5>{k[0], k[1], k[2], k[3], k[4]};
  }
  const JsonValue& v = j.at("view", what);
  const std::string vw = what + ": view";
  f.view.distance = v.at("distance_m", vw).number(vw + ".distance_m");
  f.view.phi_deg = v.at("phi_deg", vw).number(vw + ".phi_deg");
  f.view.tilt_axis_deg = v.at("tilt_axis_deg", vw).number(vw + ".tilt_axis_deg");
  f.view.roll_deg = v.at("roll_deg", vw).number(vw + ".roll_deg");
  f.view.pixel = Eigen::Vector2d(v.at("image_x", vw).number(vw + ".image_x"), v.at("image_y", vw).number(vw + ".image_y"));
  if (d.settings.experiment == Experiment::kSixdof) {
    const JsonValue& c = j.at("camera_effects", what);
    const std::string cw = what + ": camera_effects";
    CameraEffects cam;
    cam.distortion = out.distortion.value_or(d.settings.sixdof.distortion);
    cam.defocus_sigma_px = c.at("defocus_sigma_px", cw).number(cw + ".defocus_sigma_px");
    cam.noise_sigma = c.at("noise_sigma", cw).number(cw + ".noise_sigma");
    cam.noise_seed = c.at("noise_seed", cw).uint64(cw + ".noise_seed");
    cam.quantization_bits = c.at("quantization_bits", cw).integer(cw + ".quantization_bits");
    f.effect.camera = cam;
    f.sample = c.at("halton_index", cw).uint64(cw + ".halton_index");
    f.image_position = Eigen::Vector2d(c.at("image_x", cw).number(cw + ".image_x"), c.at("image_y", cw).number(cw + ".image_y"));
  }
  if (d.settings.experiment == Experiment::kConditions && f.condition != Condition::kNone) {
    f.effect.condition = f.condition;
    f.effect.strength = f.step;
  }
  return out;
}

}  // namespace

Dataset read_dataset(const std::filesystem::path& path) {
  const std::filesystem::path file =
      std::filesystem::is_directory(path) ? path / "truth.json" : path;
  const std::string text = read_file(file);  // names the path when it cannot
  try {
    const JsonValue j = parse_json(text);
    const std::string format = j.at("format", "truth.json").string("format");
    if (format != kDatasetFormat)
      throw JsonError("format '" + format + "' is not " + std::string(kDatasetFormat));
    Dataset d;
    SweepSettings& s = d.settings;
    s.experiment = parse_experiment(j.at("experiment", "truth.json").string("experiment"));
    const JsonValue& st = j.at("settings", "truth.json");
    s.scene = parse_scene(st.at("scene", "settings").string("settings.scene"));
    s.family = st.at("family", "settings").string("settings.family");
    s.tag_size = st.at("tag_size_m", "settings").number("settings.tag_size_m");
    s.seed = st.at("seed", "settings").uint64("settings.seed");
    s.trials = st.at("trials", "settings").integer("settings.trials");
    if (const JsonValue& steps = st.at("steps", "settings"); !steps.is_null())
      s.steps = read_numbers(steps, 0, "settings.steps");
    if (const JsonValue& dist = st.at("distance_m", "settings"); !dist.is_null())
      s.distance = dist.number("settings.distance_m");
    for (const auto& c : st.at("conditions", "settings").array("settings.conditions"))
      s.conditions.push_back(parse_condition(c.string("settings.conditions")));
    if (s.experiment == Experiment::kSixdof) {
      const JsonValue& x = st.at("sixdof", "settings");
      const auto range = read_numbers(x.at("distance_range_m", "settings.sixdof"), 2, "settings.sixdof.distance_range_m");
      s.sixdof.distance_min = range[0];
      s.sixdof.distance_max = range[1];
      s.sixdof.phi_max_deg = x.at("phi_max_deg", "settings.sixdof").number("settings.sixdof.phi_max_deg");
      const auto lens = read_numbers(x.at("lens", "settings.sixdof"), 5, "settings.sixdof.lens");
      for (std::size_t k = 0; k < 5; ++k) s.sixdof.distortion[k] = lens[k];
      s.sixdof.defocus_max_px = x.at("defocus_max_px", "settings.sixdof").number("settings.sixdof.defocus_max_px");
      s.sixdof.noise_max = x.at("noise_max", "settings.sixdof").number("settings.sixdof.noise_max");
      s.sixdof.margin_px = x.at("margin_px", "settings.sixdof").number("settings.sixdof.margin_px");
      s.sixdof.bins = x.at("bins", "settings.sixdof").integer("settings.sixdof.bins");
    }
    for (const auto& f : j.at("frames", "truth.json").array("frames")) d.frames.push_back(read_frame(f, d));
    // What scoring relies on, checked here so that a bad truth file is named, not the detections.
    if (d.frames.empty()) throw JsonError("frames: empty: the dataset has no frame to score");
    if (s.tag_size && !(std::isfinite(*s.tag_size) && *s.tag_size > 0))
      throw JsonError("settings.tag_size_m: must be > 0 (metres)");
    // The ids are checked against the family when it can be loaded here: a family file the dataset
    // was made with may live on another machine (the frames carry its name, what detectors report).
    std::optional<TagFamily> family;
    try {
      family = load_family(s.family);
    } catch (const std::invalid_argument&) {
      if (!names_a_family_file(s.family)) throw;  // an unknown name
    }
    std::map<std::string, std::size_t> seen;
    for (const DatasetFrame& f : d.frames) {
      const std::string what = "frame " + std::to_string(f.index);
      if (const auto [it, fresh] = seen.emplace(f.file, f.index); !fresh)
        throw JsonError(what + ": file '" + f.file + "' is also frame " + std::to_string(it->second) + "'s");
      if (family && (f.frame.frame.id < 0 || static_cast<std::size_t>(f.frame.frame.id) >= family->size()))
        throw JsonError(what + ": id " + std::to_string(f.frame.frame.id) + " is not in family " + family->name());
      if (family && canonical_family_name(f.frame.frame.family) != canonical_family_name(family->name()))
        throw JsonError(what + ": family '" + f.frame.frame.family + "' is not the dataset's (" + family->name() + ")");
      if (!(std::isfinite(f.frame.frame.tag_size) && f.frame.frame.tag_size > 0))
        throw JsonError(what + ": tag_size_m must be > 0 (metres)");
    }
    if (const JsonValue* failed = j.find("failed"))
      for (const auto& f : failed->array("failed"))
        d.failed.push_back({static_cast<std::size_t>(f.at("index", "failed").uint64("failed: index")),
                            f.at("error", "failed").string("failed: error")});
    return d;
  } catch (const std::exception& e) {  // JsonError and the parse_* functions' invalid_argument
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

}  // namespace tagbench::bench
