// make_dataset, truth_json, write_dataset: a sweep's frames and their truth as files (dataset.hpp).
#include <cstdio>
#include <set>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "dataset/dataset.hpp"
#include "tools/atomic_file.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

namespace {

const char* unit_of(const SweepFrame& f, Experiment e) {
  if (e == Experiment::kAngle) return "deg";
  if (e == Experiment::kDistance) return "m";
  if (e == Experiment::kSixdof) return "none";
  return condition_info(f.condition).unit;
}

std::string point(const Eigen::Vector2d& p) { return std::string("[") + json_number(p.x()) + ", " + json_number(p.y()) + "]"; }

std::string matrix(const Eigen::Matrix3d& m) {
  std::string s = "[";
  for (int i = 0; i < 3; ++i)
    s += std::string(i ? ", " : "") + "[" + json_number(m(i, 0)) + ", " + json_number(m(i, 1)) + ", " +
         json_number(m(i, 2)) + "]";
  return s + "]";
}

// The lens of a frame when it is not the pinhole: the distortion condition's k1, sixdof's lens.
std::optional<std::array<double, 5>> frame_distortion(const SweepFrame& f) {
  if (f.effect.camera) return f.effect.camera->distortion;
  if (f.effect.condition == Condition::kDistortion && f.effect.strength != 0)
    return std::array<double, 5>{-f.effect.strength, 0, 0, 0, 0};
  return std::nullopt;
}

std::string frame_json(const SweepFrame& f, std::size_t index, Experiment e) {
  const bool conditions = e == Experiment::kConditions;
  std::string j = "{\"file\": " + json_string(dataset_frame_file(index)) + ", \"index\": " + std::to_string(index) +
                  ", \"condition\": " + json_string(condition_name(f.condition)) +
                  ", \"strength\": " + json_number(conditions ? f.step : 0.0) + ", \"step\": " + json_number(f.step) +
                  ", \"step_unit\": " + json_string(unit_of(f, e)) + ", \"trial\": " + std::to_string(f.trial) +
                  ", \"seed\": " + std::to_string(f.seed) + ",\n     \"family\": " + json_string(f.frame.family_name.empty() ? f.frame.family : f.frame.family_name) +
                  ", \"id\": " + std::to_string(f.frame.id) + ", \"tag_size_m\": " + json_number(f.frame.tag_size) +
                  ",\n     \"R\": " + matrix(f.truth.pose.R) + ", \"t\": " +
                  json_numbers({f.truth.pose.t.x(), f.truth.pose.t.y(), f.truth.pose.t.z()}) +
                  ",\n     \"corners\": [";
  for (std::size_t k = 0; k < 4; ++k) j += (k ? ", " : "") + point(f.truth.corners[k]);
  j += "], \"black_square_px\": " + json_number(f.truth.black_square_px) + ", \"distortion\": ";
  const auto d = frame_distortion(f);
  j += d ? json_numbers({d->begin(), d->end()}) : std::string("null");
  j += ",\n     \"view\": {\"distance_m\": " + json_number(f.view.distance) + ", \"phi_deg\": " +
       json_number(f.view.phi_deg) + ", \"tilt_axis_deg\": " + json_number(f.view.tilt_axis_deg) +
       ", \"roll_deg\": " + json_number(f.view.roll_deg) + ", \"image_x\": " + json_number(f.view.pixel.x()) +
       ", \"image_y\": " + json_number(f.view.pixel.y()) + "}";
  if (const auto& c = f.effect.camera)
    j += ",\n     \"camera_effects\": {\"halton_index\": " + std::to_string(f.sample) +
         ", \"image_x\": " + json_number(f.image_position.x()) + ", \"image_y\": " + json_number(f.image_position.y()) +
         ", \"defocus_sigma_px\": " + json_number(c->defocus_sigma_px) + ", \"noise_sigma\": " +
         json_number(c->noise_sigma) + ", \"noise_seed\": " + std::to_string(c->noise_seed) +
         ", \"quantization_bits\": " + std::to_string(c->quantization_bits) + "}";
  return j + "}";
}

}  // namespace

std::string dataset_frame_file(std::size_t index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%05zu.png", index);
  return buf;
}

std::string truth_json(const SweepSettings& s, const std::vector<SweepFrame>& frames,
                       const std::vector<FailedFrame>& failed) {
  const CameraIntrinsics K = render_camera();
  const bool sixdof = s.experiment == Experiment::kSixdof;
  std::string j = "{\n  \"format\": " + json_string(kDatasetFormat) + ",\n  \"tool\": \"tagbench dataset export\",\n";
  j += "  \"experiment\": " + json_string(experiment_name(s.experiment)) + ",\n";
  j += "  \"settings\": {\"scene\": " + json_string(scene_name(s.scene)) + ", \"family\": " + json_string(s.family) +
       ", \"tag_size_m\": " + json_number(*s.tag_size) + ", \"seed\": " + std::to_string(s.seed) +
       ", \"trials\": " + std::to_string(s.trials) + ",\n    \"steps\": " +
       (s.experiment == Experiment::kConditions || sixdof ? std::string("null") : json_numbers(s.steps)) +
       ", \"distance_m\": " + (s.distance ? json_number(*s.distance) : std::string("null")) + ", \"conditions\": [";
  for (std::size_t i = 0; i < s.conditions.size(); ++i) j += (i ? ", " : "") + json_string(condition_name(s.conditions[i]));
  if (sixdof) {
    const SixdofSettings& x = s.sixdof;
    j += "],\n    \"sixdof\": {\"distance_range_m\": " + json_numbers({x.distance_min, x.distance_max}) +
         ", \"phi_max_deg\": " + json_number(x.phi_max_deg) +
         ", \"lens\": " + json_numbers({x.distortion.begin(), x.distortion.end()}) +
         ", \"defocus_max_px\": " + json_number(x.defocus_max_px) + ", \"noise_max\": " + json_number(x.noise_max) +
         ", \"margin_px\": " + json_number(x.margin_px) + ", \"bins\": " + std::to_string(x.bins) + "}},\n";
  } else {
    j += "]},\n";
  }
  j += "  \"camera\": {\"width\": " + std::to_string(kRenderWidth) + ", \"height\": " + std::to_string(kRenderHeight) +
       ", \"fx\": " + json_number(K.fx) + ", \"fy\": " + json_number(K.fy) + ", \"cx\": " + json_number(K.cx) +
       ", \"cy\": " + json_number(K.cy) +
       ", \"distortion\": " +
       (sixdof ? json_numbers({s.sixdof.distortion.begin(), s.sixdof.distortion.end()}) : std::string("[0, 0, 0, 0, 0]")) +
       ",\n    \"model\": " +
       json_string("pinhole; distortion is OpenCV's k1, k2, p1, p2, k3 (a frame's own \"distortion\" overrides it)") +
       ", \"renderer\": \"POV-Ray 3.7\"},\n";
  j += "  \"conventions\": {\"pixel_centres\": \"integer\", \"corner_order\": \"tl-tr-br-bl\", \"tag_frame_axes\": "
       "\"x,y,z\", \"intensity_gamma\": 1,\n    \"words\": " +
       json_string("pixel centres at integer coordinates (the top-left pixel's centre is (0, 0)); corners: the "
                   "black square's outer corners, top-left, top-right, bottom-right, bottom-left of the printed tag; "
                   "camera frame: x right, y down, z forward; tag frame: origin at the tag centre, x toward the "
                   "printed right edge, y toward the printed bottom edge, z into the tag; X_camera = R X_tag + t, "
                   "metres; tag_size_m: the black square's edge; intensities are linear (intensity_gamma 1: POV-Ray's "
                   "File_Gamma=1.0), not gamma-encoded as a camera's JPEGs are") +
       "},\n";
  j += "  \"frames\": [";
  std::set<std::size_t> bad;
  for (const auto& f : failed) bad.insert(f.frame);
  bool first = true;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (bad.count(i)) continue;
    j += std::string(first ? "\n    " : ",\n    ") + frame_json(frames[i], i, s.experiment);
    first = false;
  }
  j += first ? "],\n" : "\n  ],\n";
  j += "  \"failed\": [";
  for (std::size_t i = 0; i < failed.size(); ++i)
    j += std::string(i ? ", " : "") + "{\"index\": " + std::to_string(failed[i].frame) +
         ", \"error\": " + json_string(failed[i].error) + "}";
  j += "]\n}\n";
  return j;
}

DatasetFiles make_dataset(const SweepSettings& settings, const RenderOptions& render_options,
                          const std::function<void(std::size_t, std::size_t)>& frame_done) {
  SweepSettings in = settings;
  in.detectors = {comparator_names().front()};  // ours: it knows every family (the others are not run)
  const SweepSettings s = resolve_settings(in);
  const std::vector<SweepFrame> frames = plan_sweep(s);
  std::vector<FramePose> poses;
  for (const auto& f : frames) poses.push_back(f.frame);
  const RenderReport report = render_frames(poses, scene_template(s.scene), render_options);
  DatasetFiles out;
  out.planned = frames.size();
  out.rendered = report.rendered;
  out.from_cache = report.from_cache;
  std::vector<FailedFrame> failed;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (!report.frames[i].ok()) failed.push_back({i, report.frames[i].error});
  out.failed = failed.size();
  if (!frames.empty() && failed.size() == frames.size())
    throw std::runtime_error("none of the " + std::to_string(frames.size()) + " frames rendered: " + failed.front().error);
  std::string gray_path;
  cv::Mat gray;
  std::size_t done = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!report.frames[i].ok()) continue;
    const std::string png = report.frames[i].png.string();
    if (png != gray_path) {
      gray = read_frame_gray(png);
      gray_path = png;
    }
    std::vector<unsigned char> bytes;
    if (!cv::imencode(".png", apply_effect(gray, frames[i]), bytes))
      throw std::runtime_error("cannot encode frame " + std::to_string(i) + " as PNG");
    out.frames.emplace_back(dataset_frame_file(i), std::string(bytes.begin(), bytes.end()));
    if (frame_done) frame_done(++done, frames.size() - failed.size());
  }
  out.truth_json = truth_json(s, frames, failed);
  return out;
}

void write_dataset(const std::filesystem::path& dir, const DatasetFiles& files) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> old_frames;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw std::runtime_error(dir.string() + ": not a directory");
    if (fs::exists(dir / "truth.json", ec)) {
      // Only a dataset's own truth.json (its format line) makes the folder an earlier dataset.
      std::string text;
      try {
        text = read_file(dir / "truth.json");
      } catch (const std::exception&) {
      }
      if (text.find(std::string("\"format\": \"") + kDatasetFormat + "\"") == std::string::npos)
        throw std::runtime_error(dir.string() + ": not empty and not a dataset (its truth.json is not a tagbench dataset's): "
                                 "choose another --out");
      try {
        for (const auto& f : read_dataset(dir).frames) old_frames.push_back(f.file);
      } catch (const std::exception&) {
        // An unreadable earlier truth.json: its frames are kept, only the new set is written.
      }
    } else if (!fs::is_empty(dir, ec)) {
      throw std::runtime_error(dir.string() + ": not empty and not a dataset (no truth.json): choose another --out");
    }
  }
  const bool made = fs::create_directories(dir);
  remove_stale_temporaries(dir);
  std::vector<std::pair<fs::path, std::string>> out;
  std::set<std::string> names;
  for (const auto& [name, bytes] : files.frames) {
    out.emplace_back(dir / name, bytes);
    names.insert(name);
  }
  out.emplace_back(dir / "truth.json", files.truth_json);
  try {
    write_files_atomic(out);
  } catch (...) {
    if (made) fs::remove(dir, ec);  // only if still empty
    throw;
  }
  for (const auto& name : old_frames)
    if (!names.count(name)) fs::remove(dir / name, ec);  // an earlier dataset's frames this one has not
}

}  // namespace tagbench::bench
