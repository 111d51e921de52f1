// score_detections, convention_hint, score_sidecar_json (score.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>

#include "codes/families.hpp"
#include "raytrace/sixdof.hpp"
#include "score/score.hpp"
#include "tools/format.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

namespace {


// As the sweeps score a frame (score_frame, sweeps.hpp), keeping the matched detection.
SweepRow score_and_match(const std::vector<Found>& found, double ms, const std::string& detector, std::size_t index,
                         const SweepFrame& f, std::vector<std::pair<Found, const SweepFrame*>>& matched) {
  const Found* best = nullptr;
  SweepRow r = bench::score_frame(found, ms, detector, index, f, &best);
  if (best) matched.emplace_back(*best, &f);
  return r;
}

double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

// The 24 rotations that permute the axes (signed permutation matrices of determinant +1).
std::vector<Eigen::Matrix3d> axis_rotations() {
  std::vector<Eigen::Matrix3d> out;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms)
    for (int s = 0; s < 8; ++s) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) m(i, p[i]) = (s >> i) & 1 ? -1 : 1;
      if (m.determinant() > 0) out.push_back(m);
    }
  return out;
}

}  // namespace

std::string convention_hint(const std::vector<std::pair<Found, const SweepFrame*>>& matched, const Convention& declared,
                            const std::string& name) {
  if (matched.empty()) return {};
  // Corners: our corner j is at the detection's corner perm[j], shifted by delta.
  struct Fix {
    std::array<int, 4> perm;
    double delta;
    double median_rms;
  };
  const auto corner_median = [&](const std::array<int, 4>& perm, double delta) {
    std::vector<double> rms;
    for (const auto& [f, frame] : matched) {
      double sum = 0;
      for (std::size_t j = 0; j < 4; ++j)
        sum += (f.corners[static_cast<std::size_t>(perm[j])] + Eigen::Vector2d::Constant(delta) - frame->truth.corners[j])
                   .squaredNorm();
      rms.push_back(std::sqrt(sum / 4));
    }
    return median(rms);
  };
  const Fix base{{0, 1, 2, 3}, 0, corner_median({0, 1, 2, 3}, 0)};
  Fix best = base;
  for (int reversed = 0; reversed < 2; ++reversed)
    for (int r = 0; r < 4; ++r)
      for (const double delta : {0.0, 0.5, -0.5}) {
        std::array<int, 4> perm{};
        for (int j = 0; j < 4; ++j) perm[static_cast<std::size_t>(j)] = reversed ? (r - j + 4) % 4 : (j + r) % 4;
        const double m = corner_median(perm, delta);
        if (m < best.median_rms) best = {perm, delta, m};
      }
  std::vector<std::string> options;
  std::string numbers;
  if (base.median_rms > 0.4 && best.median_rms < 0.5 * base.median_rms) {
    std::array<int, 4> order = declared.order;  // the detector's k-th corner is our order'[k]
    for (std::size_t k = 0; k < 4; ++k)
      for (int j = 0; j < 4; ++j)
        if (best.perm[static_cast<std::size_t>(j)] == declared.order[k]) order[k] = j;
    if (order != declared.order) options.push_back("--corner-order " + corner_order_name(order));
    if (best.delta != 0) options.push_back("--pixel-offset " + format_number(declared.pixel_offset - best.delta, "%.10g"));
    numbers = "median corner RMS " + format_number(base.median_rms, "%.3g") + " px -> " +
              format_number(best.median_rms, "%.3g") + " px";
  }
  // Poses: R_ours B for the 24 axis rotations B.
  const auto orientation_median = [&](const Eigen::Matrix3d& b) {
    std::vector<double> err;
    for (const auto& [f, frame] : matched) {
      if (!f.pose) continue;
      Found g = f;
      g.pose->R = f.pose->R * b;
      err.push_back(found_errors(g, frame->truth).orientation_deg);
    }
    return median(err);
  };
  const double pose_base = orientation_median(Eigen::Matrix3d::Identity());
  if (std::isfinite(pose_base) && pose_base > 5) {
    Eigen::Matrix3d best_b = Eigen::Matrix3d::Identity();
    double best_m = pose_base;
    for (const auto& b : axis_rotations())
      if (const double m = orientation_median(b); m < best_m) best_m = m, best_b = b;
    if (best_m < pose_base / 3) {
      options.push_back("--tag-frame " + tag_frame_name(declared.tag_axes * best_b));
      numbers += (numbers.empty() ? "" : ", ") + std::string("median orientation error ") +
                 format_number(pose_base, "%.3g") + " deg -> " + format_number(best_m, "%.3g") + " deg";
    }
  }
  if (options.empty()) return {};
  std::string line = name + " fits the truth far better declared with";
  for (const auto& o : options) line += " " + o;
  return line + " (" + numbers + ")";
}

ScoreResult score_detections(const Dataset& dataset, const std::filesystem::path& dataset_dir,
                             const std::vector<ImageDetections>& lines, const std::string& source,
                             const std::string& name, const Convention& convention) {
  namespace fs = std::filesystem;
  std::map<std::string, std::size_t> by_file;
  for (std::size_t i = 0; i < dataset.frames.size(); ++i) by_file[dataset.frames[i].file] = i;
  std::error_code ec;
  const fs::path dir = fs::weakly_canonical(fs::absolute(dataset_dir), ec);
  std::vector<const ImageDetections*> of_frame(dataset.frames.size(), nullptr);
  for (const ImageDetections& l : lines) {
    const std::string where = source + " line " + std::to_string(l.line) + ": image '" + l.image + "'";
    const fs::path p(l.image);
    std::string key = l.image;
    if (p.has_parent_path()) {
      key = p.filename().string();
      const fs::path parent = fs::weakly_canonical(fs::absolute(p).parent_path(), ec);
      if (parent != dir) throw std::runtime_error(where + " is not in the dataset folder " + dataset_dir.string());
    }
    const auto it = by_file.find(key);
    if (it == by_file.end()) throw std::runtime_error(where + " is not a frame of the dataset");
    if (of_frame[it->second])
      throw std::runtime_error(where + " given twice (lines " + std::to_string(of_frame[it->second]->line) + " and " +
                               std::to_string(l.line) + ")");
    if (!l.error.empty()) throw std::runtime_error(where + ": the detector failed: " + l.error);
    of_frame[it->second] = &l;
  }
  std::size_t missing = 0;
  for (const auto* l : of_frame) missing += l == nullptr;
  for (std::size_t i = 0; i < of_frame.size(); ++i)
    if (!of_frame[i])
      throw std::runtime_error(source + ": no line for image '" + dataset.frames[i].file + "' (" +
                               std::to_string(missing) + " of " + std::to_string(of_frame.size()) +
                               " frames have none; every frame needs a line, \"detections\": [] when nothing was found)");

  ScoreResult r;
  r.sweep.settings = dataset.settings;
  r.sweep.settings.detectors = {name};
  std::vector<std::pair<Found, const SweepFrame*>> matched;
  r.sweep.frames.reserve(dataset.frames.size());
  for (const auto& f : dataset.frames) {
    r.sweep.frames.push_back(f.frame);
    r.plan_index.push_back(f.index);
  }
  for (std::size_t i = 0; i < dataset.frames.size(); ++i) {
    std::vector<Found> ours;
    for (const Found& f : of_frame[i]->found) ours.push_back(to_ours(f, convention));
    r.sweep.rows.push_back(score_and_match(ours, of_frame[i]->ms, name, i, r.sweep.frames[i], matched));
  }
  r.sweep.distinct_frames = dataset.frames.size();
  r.hint = convention_hint(matched, convention, name);
  return r;
}

std::string score_sidecar_json(const ScoreResult& r, const std::filesystem::path& dataset,
                               const std::string& detections, const Convention& c) {
  const SweepSettings& s = r.sweep.settings;
  const CameraIntrinsics K = render_camera();
  const std::string stem = result_stem(s);
  const bool sixdof = s.experiment == Experiment::kSixdof;
  std::string j = "{\n  \"tool\": \"tagbench score\",\n  \"experiment\": " + json_string(experiment_name(s.experiment)) +
                  ",\n  \"dataset\": " + json_string(dataset.string()) + ", \"detections\": " + json_string(detections) +
                  ",\n  \"detector\": " + json_string(s.detectors.front()) +
                  ",\n  \"convention\": {\"corner_order\": " + json_string(corner_order_name(c.order)) +
                  ", \"pixel_offset\": " + json_number(c.pixel_offset) +
                  ", \"tag_frame\": " + json_string(tag_frame_name(c.tag_axes)) + "},\n  \"hint\": " +
                  (r.hint.empty() ? std::string("null") : json_string(r.hint)) + ",\n";
  j += "  \"files\": {\"rows\": " + json_string(stem + ".csv") + ", \"summary\": " + json_string(stem + "_summary.csv") +
       "},\n";
  j += "  \"settings\": {\"scene\": " + json_string(scene_name(s.scene)) + ", \"family\": " + json_string(s.family) +
       ", \"tag_size_m\": " + json_number(*s.tag_size) + ", \"seed\": " + std::to_string(s.seed) +
       ", \"trials\": " + std::to_string(s.trials) + ",\n    \"steps\": " +
       (s.experiment == Experiment::kConditions || sixdof ? std::string("null") : json_numbers(s.steps)) +
       ", \"distance_m\": " + (s.distance ? json_number(*s.distance) : std::string("null")) +
       ", \"detectors\": [" + json_string(s.detectors.front()) + "]" +
       (sixdof ? ",\n    \"sixdof\": " + sixdof_settings_json(s) : std::string()) + "},\n";
  j += "  \"camera\": {\"width\": " + std::to_string(kRenderWidth) + ", \"height\": " + std::to_string(kRenderHeight) +
       ", \"fx\": " + json_number(K.fx) + ", \"fy\": " + json_number(K.fy) + ", \"cx\": " + json_number(K.cx) +
       ", \"cy\": " + json_number(K.cy) +
       (sixdof ? ", \"distortion\": " + json_numbers({s.sixdof.distortion.begin(), s.sixdof.distortion.end()})
               : std::string()) +
       "},\n";
  j += "  \"measures\": " +
       json_string("as tagbench raytrace: detected_right_id, wrong_id, errors of the right-id detection nearest the "
                   "truth (orientation = the angle of R_est^T R_true, distance = | |t_est| - |t_true| |, corner RMS); "
                   "ms: the line's \"ms\" (empty when not given); summaries: Wilson 95 % interval, percentiles over "
                   "the detected frames") +
       ",\n  \"frames\": " + std::to_string(r.sweep.frames.size()) + "\n}\n";
  return j;
}

}  // namespace tagbench::bench
