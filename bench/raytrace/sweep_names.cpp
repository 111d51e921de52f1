// The sweeps' names: experiments, result stems, the conditions' table, scenes.
#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "codes/families.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::bench {

const char* experiment_name(Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "angle";
    case Experiment::kDistance: return "distance";
    case Experiment::kConditions: return "conditions";
    case Experiment::kSixdof: return "sixdof";
  }
  return "?";
}

const char* result_stem(Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "fig9_angle";
    case Experiment::kDistance: return "fig10_distance";
    case Experiment::kConditions: return "conditions";
    case Experiment::kSixdof: return "sixdof";
  }
  return "?";
}

std::string result_stem(const SweepSettings& s) {
  std::string stem = result_stem(s.experiment);
  const std::string family = canonical_family_name(s.family);
  if (family == "36h11") return stem;
  std::string name = std::filesystem::path(family).stem().string();
  if (name.empty()) name = family;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return stem + "_" + name;
}

const std::vector<ConditionInfo>& condition_table() {
  static const std::vector<ConditionInfo> table{
      {Condition::kNoise, "noise", "sigma_levels",
       "sensor noise: Gaussian noise of standard deviation `strength` (8-bit levels) added to every pixel of the "
       "rendered 8-bit image, rounded and clipped to 0..255, seeded per frame",
       {0, 4, 8, 16, 32}},
      {Condition::kBlur, "blur", "sigma_px",
       "defocus: a Gaussian blur of standard deviation `strength` pixels of the rendered image (cv::GaussianBlur, "
       "border replicated)",
       {0, 1, 2, 3, 4}},
      {Condition::kGradient, "gradient", "light_lost",
       "lighting gradient: the image multiplied by a linear ramp from 1 down to 1 - `strength` across the black "
       "square along a random image direction (constant beyond it)",
       {0, 0.25, 0.5, 0.75, 0.9}},
      {Condition::kOcclusion, "occlusion", "edge_fraction",
       "a border edge partly occluded: a dark grey (0.35) patch rendered just in front of the tag over the middle "
       "`strength` of the printed bottom edge of the black square, from half into the black ring out past the "
       "white ring",
       {0, 0.2, 0.4, 0.6, 0.8}},
      {Condition::kBent, "bent", "bend_deg",
       "a bent tag: folded along its vertical centre line, each half turned by `strength`/2 degrees with its "
       "outer edge toward the camera (rendered); truth: the nominal pose, the bent corners",
       {0, 10, 20, 30, 40}},
      {Condition::kDistortion, "distortion", "minus_k1",
       "lens distortion: barrel, OpenCV's radial model with k1 = -`strength` (k2 = p1 = p2 = k3 = 0) about the "
       "principal point, applied to the render by remapping (bilinear); truth: the distorted corners. Ours and "
       "aruco's pose (solvePnP IPPE_SQUARE, as estimatePoseSingleMarkers) get the coefficients; libapriltag's "
       "estimate_tag_pose has no distortion model and gets the pinhole intrinsics",
       {0, 0.05, 0.1, 0.2, 0.3}},
  };
  return table;
}

const ConditionInfo& condition_info(Condition c) {
  for (const auto& i : condition_table())
    if (i.condition == c) return i;
  throw std::invalid_argument("no condition 'none'");
}

const char* condition_name(Condition c) { return c == Condition::kNone ? "none" : condition_info(c).name; }

Condition parse_condition(const std::string& name) {
  std::string known;
  for (const auto& i : condition_table()) {
    if (name == i.name) return i.condition;
    known += (known.empty() ? "" : ", ") + std::string(i.name);
  }
  throw std::invalid_argument("unknown condition '" + name + "' (" + known + ")");
}

SceneKind parse_scene(const std::string& name) {
  if (name == "plain") return SceneKind::kPlain;
  if (name == "realistic") return SceneKind::kRealistic;
  throw std::invalid_argument("unknown scene '" + name + "' (plain, realistic)");
}

Experiment parse_experiment(const std::string& name) {
  for (const Experiment e : {Experiment::kAngle, Experiment::kDistance, Experiment::kConditions, Experiment::kSixdof})
    if (name == experiment_name(e)) return e;
  throw std::invalid_argument("unknown experiment '" + name + "' (angle, distance, conditions, sixdof)");
}

}  // namespace tagbench::bench
