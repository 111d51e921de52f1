#include "raytrace/sweeps.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <tuple>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "codes/families.hpp"
#include "detect/detector.hpp"
#include "stats.hpp"
#include "tools/format.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = M_PI / 180;

// ---- randomness: splitmix64, portable (no std:: distributions, whose outputs are library-defined) ----

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t derive(std::uint64_t a, std::uint64_t b) {
  std::uint64_t s = a ^ (b * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL);
  splitmix64(s);
  return splitmix64(s);
}

struct Rng {
  std::uint64_t state;
  std::uint64_t next() { return splitmix64(state); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double normal() {                                                            // Box-Muller
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }
};

// ---- conditions ----------------------------------------------------------------------------------------

constexpr double kOccluderGrey = 0.35;
constexpr double kConditionsMaxPhi = 30;

std::string scene_finish(SceneKind scene) {
  // As the templates finish their tag: self-lit in the plain scene, diffuse in the realistic one.
  return scene == SceneKind::kPlain ? "finish { ambient 1 diffuse 0 }" : "finish { ambient 0.15 diffuse 0.8 }";
}

// A dark grey patch just in front of the tag (POV-Ray's tag coordinates: x right, y up, z into the
// tag) over the middle `fraction` of the printed bottom border edge, from half into the black ring out
// past the white ring.
std::string occluder_sdl(double fraction, double tag_size, int cells, SceneKind scene) {
  const double s = tag_size, cell = s / (cells - 2);
  const double x0 = -fraction * s / 2, x1 = fraction * s / 2;
  const double y0 = -s / 2 - 1.5 * cell, y1 = -s / 2 + 0.5 * cell;
  const double z0 = -0.03 * s, z1 = -0.01 * s;
  return "  box { <" + format_cell(x0, "%.17g") + ", " + format_cell(y0, "%.17g") + ", " + format_cell(z0, "%.17g") +
         ">, <" + format_cell(x1, "%.17g") + ", " + format_cell(y1, "%.17g") + ", " + format_cell(z1, "%.17g") +
         ">\n    texture { pigment { color rgb " + format_cell(kOccluderGrey, "%.10g") + " } " + scene_finish(scene) +
         " }\n    transform { TagPose } }";
}

// The tag folded along its vertical centre line: the template's flat tag is moved out of view (behind
// the camera) and two halves are drawn instead, each turned by half the bend about the centre line
// with its outer edge toward the camera.
std::string bent_sdl(double bend_deg, SceneKind scene) {
  const double a = bend_deg / 2 * kDeg, c = std::cos(a), sn = std::sin(a);
  const auto half = [&](const char* poly, double sgn) {
    const double s = sgn * sn;  // x' = c x + s z, z' = -s x + c z (POV-Ray's matrix takes row vectors)
    return std::string("    polygon { 4, ") + poly +
           "\n      texture { pigment { image_map { png TagPng gamma 1.0 once } } " + scene_finish(scene) +
           " }\n      translate <-0.5, -0.5, 0> scale <TagWidth, TagWidth, 1>\n      matrix <" +
           format_cell(c, "%.17g") + ", 0, " + format_cell(-s, "%.17g") + ", 0, 1, 0, " + format_cell(s, "%.17g") +
           ", 0, " + format_cell(c, "%.17g") + ", 0, 0, 0> }\n";
  };
  return "  #declare BentPose = transform { TagPose }\n"
         "  #declare TagPose = transform { translate <0, 0, -1000000> }\n"
         "  union {\n" +
         half("<0, 0>, <0.5, 0>, <0.5, 1>, <0, 1>", -1) + half("<0.5, 0>, <1, 0>, <1, 1>, <0.5, 1>", 1) +
         "    transform { BentPose } }";
}

Eigen::Vector2d project(const Pose& p, const Eigen::Vector3d& X) {
  const CameraIntrinsics K = render_camera();
  const Eigen::Vector3d c = p.R * X + p.t;
  return {K.fx * c.x() / c.z() + K.cx, K.fy * c.y() / c.z() + K.cy};
}

double mean_edge(const Corners& c) {
  double sum = 0;
  for (std::size_t i = 0; i < 4; ++i) sum += (c[(i + 1) % 4] - c[i]).norm();
  return sum / 4;
}

// OpenCV's radial model with k1 only, about the principal point, in pixels.
Eigen::Vector2d distort_pixel(const Eigen::Vector2d& p, double k1) {
  const CameraIntrinsics K = render_camera();
  const double x = (p.x() - K.cx) / K.fx, y = (p.y() - K.cy) / K.fy, r2 = x * x + y * y;
  const double f = 1 + k1 * r2;
  return {K.fx * x * f + K.cx, K.fy * y * f + K.cy};
}

// For every pixel of the distorted image, where it comes from in the pinhole render (Newton on
// r (1 + k1 r^2) = r_d, from r_d: monotone for k1 < 0). Points the model folds over (no preimage) are
// sent far out along their ray, so the border is replicated there.
const std::pair<cv::Mat, cv::Mat>& distortion_maps(double k1) {
  static std::mutex mu;
  static std::map<double, std::pair<cv::Mat, cv::Mat>> maps;
  std::lock_guard lock(mu);
  if (auto it = maps.find(k1); it != maps.end()) return it->second;
  const CameraIntrinsics K = render_camera();
  cv::Mat mx(kRenderHeight, kRenderWidth, CV_32FC1), my(kRenderHeight, kRenderWidth, CV_32FC1);
  for (int v = 0; v < kRenderHeight; ++v) {
    for (int u = 0; u < kRenderWidth; ++u) {
      const double xd = (u - K.cx) / K.fx, yd = (v - K.cy) / K.fy, rd = std::hypot(xd, yd);
      double scale = 1;
      if (rd > 0 && k1 != 0) {
        double r = rd;
        bool ok = false;
        for (int it = 0; it < 60; ++it) {
          const double g = r * (1 + k1 * r * r) - rd, dg = 1 + 3 * k1 * r * r;
          if (!(dg > 1e-9)) break;
          const double step = g / dg;
          r -= step;
          if (std::abs(step) < 1e-14) {
            ok = std::abs(r * (1 + k1 * r * r) - rd) < 1e-9 && 1 + 3 * k1 * r * r > 0;
            break;
          }
        }
        scale = ok ? r / rd : 1e3;
      }
      mx.at<float>(v, u) = static_cast<float>(K.fx * xd * scale + K.cx);
      my.at<float>(v, u) = static_cast<float>(K.fy * yd * scale + K.cy);
    }
  }
  return maps.emplace(k1, std::make_pair(mx, my)).first->second;
}

using DetectorSet = std::vector<std::unique_ptr<Comparator>>;

DetectorSet make_detectors(const SweepSettings& s, std::optional<double> k1) {
  ComparatorSetup setup;
  setup.family = s.family;
  setup.camera = render_camera();
  setup.tag_size = *s.tag_size;
  if (k1) setup.distortion = std::array<double, 5>{*k1, 0, 0, 0, 0};
  DetectorSet set;
  for (const auto& name : s.detectors) set.push_back(make_comparator(name, setup));
  return set;
}

SweepRow row_of(const DetectorOutput& out, const std::string& detector, std::size_t index, const SweepFrame& f) {
  SweepRow r;
  r.frame = index;
  r.detector = detector;
  r.ms = out.ms;
  r.orientation_error_deg = r.distance_error_m = r.distance_error_percent = r.corner_rms_px = kNaN;
  r.decision_margin = kNaN;
  const Found* best = nullptr;
  FoundErrors best_e;
  for (const Found& found : out.found) {
    if (found.id != f.frame.id || canonical_family_name(found.family) != canonical_family_name(f.frame.family)) {
      r.wrong_id = true;
      continue;
    }
    const FoundErrors e = found_errors(found, f.truth);
    if (!best || e.corner_rms_px < best_e.corner_rms_px) {
      best = &found;
      best_e = e;
    }
  }
  if (best) {
    r.detected_right_id = true;
    r.corner_rms_px = best_e.corner_rms_px;
    r.orientation_error_deg = best_e.orientation_deg;
    r.distance_error_m = best_e.distance_m;
    r.distance_error_percent = best_e.distance_percent;
    r.decision_margin = best->decision_margin;
  }
  return r;
}

const char* step_unit(const SweepFrame& f, Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "deg";
    case Experiment::kDistance: return "m";
    case Experiment::kConditions: return condition_info(f.condition).unit;
  }
  return "";
}

int tag_cells_across(const std::string& family) {
  const int bits = load_family(family).bits();
  const int d = static_cast<int>(std::lround(std::sqrt(static_cast<double>(bits))));
  return d + 4;
}

}  // namespace

// ---- names ---------------------------------------------------------------------------------------------

const char* experiment_name(Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "angle";
    case Experiment::kDistance: return "distance";
    case Experiment::kConditions: return "conditions";
  }
  return "?";
}

const char* result_stem(Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "fig9_angle";
    case Experiment::kDistance: return "fig10_distance";
    case Experiment::kConditions: return "conditions";
  }
  return "?";
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
  for (const Experiment e : {Experiment::kAngle, Experiment::kDistance, Experiment::kConditions})
    if (name == experiment_name(e)) return e;
  throw std::invalid_argument("unknown experiment '" + name + "' (angle, distance, conditions)");
}

// ---- settings and plan -------------------------------------------------------------------------------

std::vector<double> default_steps(Experiment e) {
  std::vector<double> v;
  if (e == Experiment::kAngle) {
    for (int phi = 0; phi <= 85; phi += 5) v.push_back(phi);
  } else if (e == Experiment::kDistance) {
    for (int d = 2; d <= 10; ++d) v.push_back(d);
    for (int k = 5; k <= 24; ++k) v.push_back(2.5 * k);  // 12.5 .. 60
  }
  return v;
}

double position_radius_px(Experiment e) { return e == Experiment::kDistance ? 20 : 100; }

SweepSettings resolve_settings(const SweepSettings& in) {
  SweepSettings s = in;
  const std::string what = std::string(experiment_name(s.experiment)) + " sweep: ";
  if (s.trials <= 0) throw std::invalid_argument("trials must be > 0 (got " + std::to_string(s.trials) + ")");
  if (!s.tag_size) s.tag_size = s.experiment == Experiment::kDistance ? 1.0 : 0.166;
  if (!(*s.tag_size > 0) || !std::isfinite(*s.tag_size))
    throw std::invalid_argument("tag size must be > 0 metres (got " + format_cell(*s.tag_size, "%.10g") + ")");
  if (s.detectors.empty()) s.detectors = comparator_names();
  std::set<std::string> seen;
  for (const auto& d : s.detectors) {
    const auto& known = comparator_names();
    if (std::find(known.begin(), known.end(), d) == known.end() && !is_ours_variant(d)) {
      std::string list;
      for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown detector '" + d + "' (" + list + ")");
    }
    if (!seen.insert(d).second) throw std::invalid_argument("detector '" + d + "' given twice");
  }
  load_family(s.family);  // an unknown family fails here
  for (const auto& d : s.detectors) {  // and one a detector does not know ("libapriltag has no family ...")
    ComparatorSetup setup;
    setup.family = s.family;
    make_comparator(d, setup);
  }
  if (s.experiment == Experiment::kConditions) {
    if (!s.steps.empty())
      throw std::invalid_argument(what + "takes no steps (each condition has its strengths; choose conditions)");
    if (s.conditions.empty())
      for (const auto& i : condition_table()) s.conditions.push_back(i.condition);
    std::set<Condition> cs;
    for (const Condition c : s.conditions) {
      if (c == Condition::kNone) throw std::invalid_argument(what + "no condition 'none'");
      if (!cs.insert(c).second) throw std::invalid_argument(std::string("condition '") + condition_name(c) + "' given twice");
    }
  } else if (!s.conditions.empty()) {
    throw std::invalid_argument(what + "conditions belong to the conditions sweep");
  }
  if (s.experiment == Experiment::kDistance) {
    if (s.distance) throw std::invalid_argument(what + "its distances are its steps (not a fixed distance)");
  } else {
    if (!s.distance) s.distance = 1.0;
    if (!(*s.distance > 0) || !std::isfinite(*s.distance))
      throw std::invalid_argument("distance must be > 0 metres (got " + format_cell(*s.distance, "%.10g") + ")");
  }
  if (s.experiment != Experiment::kConditions) {
    if (s.steps.empty()) s.steps = default_steps(s.experiment);
    std::set<double> steps;
    for (const double v : s.steps) {
      if (s.experiment == Experiment::kAngle && !(v >= 0 && v < 90))
        throw std::invalid_argument("angle " + format_cell(v, "%.10g") + " is outside [0, 90) degrees");
      if (s.experiment == Experiment::kDistance && (!(v > 0) || !std::isfinite(v)))
        throw std::invalid_argument("distance must be > 0 metres (got " + format_cell(v, "%.10g") + ")");
      if (!steps.insert(v).second) throw std::invalid_argument("step " + format_cell(v, "%.10g") + " given twice");
    }
  }
  return s;
}

double view_angle_deg(const Pose& pose) {
  const Eigen::Vector3d normal = -pose.R.col(2), to_camera = -pose.t.normalized();
  return std::atan2(normal.cross(to_camera).norm(), normal.dot(to_camera)) / kDeg;  // exact near 0 too
}

std::vector<SweepFrame> plan_sweep(const SweepSettings& in) {
  const SweepSettings s = resolve_settings(in);
  const TagFamily family = load_family(s.family);
  const int cells = tag_cells_across(s.family);
  const double tag = *s.tag_size;
  const double radius = position_radius_px(s.experiment);
  const CameraIntrinsics K = render_camera();

  struct Draw {
    std::uint64_t seed;
    int id;
    double tilt, roll, phi, gradient_dir;
    Eigen::Vector2d pixel;
  };
  std::vector<Draw> draws;
  for (int t = 0; t < s.trials; ++t) {
    Draw d;
    d.seed = derive(derive(s.seed, static_cast<std::uint64_t>(s.experiment) + 1), static_cast<std::uint64_t>(t));
    Rng rng{d.seed};
    d.id = static_cast<int>(rng.next() % family.size());
    d.tilt = 360 * rng.uniform();
    d.roll = 360 * rng.uniform();
    const double r = radius * std::sqrt(rng.uniform()), a = 2 * M_PI * rng.uniform();
    d.pixel = Eigen::Vector2d(K.cx + r * std::cos(a), K.cy + r * std::sin(a));
    d.phi = kConditionsMaxPhi * rng.uniform();
    d.gradient_dir = 360 * rng.uniform();
    draws.push_back(d);
  }

  std::vector<SweepFrame> frames;
  const auto add = [&](const Draw& d, int trial, double step, const ViewSpec& view, Condition c, double strength,
                       std::size_t strength_index) {
    SweepFrame f;
    f.condition = c;
    f.step = step;
    f.trial = trial;
    f.seed = d.seed;
    f.view = view;
    f.frame.pose = view_pose(view);
    f.frame.family = s.family;
    f.frame.id = d.id;
    f.frame.tag_size = tag;
    f.truth = ground_truth(f.frame);
    // The whole printed tag must be in view.
    FramePose whole = f.frame;
    whole.tag_size = tag * cells / (cells - 2);
    for (const auto& p : ground_truth(whole).corners) {
      if (!(p.x() >= 0 && p.x() <= kRenderWidth - 1 && p.y() >= 0 && p.y() <= kRenderHeight - 1)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%.4g m", view.distance);
        throw std::invalid_argument(std::string("the tag does not fit in the 400 x 400 image at ") + buf +
                                    " (the whole printed tag must be in view): use a larger distance or a smaller "
                                    "tag size");
      }
    }
    if (strength != 0) {
      f.effect.condition = c;
      f.effect.strength = strength;
      switch (c) {
        case Condition::kNoise:
          f.effect.seed = derive(derive(d.seed, static_cast<std::uint64_t>(c)), strength_index);
          break;
        case Condition::kGradient: f.effect.direction_deg = d.gradient_dir; break;
        case Condition::kOcclusion: f.frame.extra_sdl = occluder_sdl(strength, tag, cells, s.scene); break;
        case Condition::kBent: {
          f.frame.extra_sdl = bent_sdl(strength, s.scene);
          const double a = strength / 2 * kDeg, h = tag / 2;
          const double xs[4] = {-1, 1, 1, -1}, ys[4] = {-1, -1, 1, 1};
          for (std::size_t k = 0; k < 4; ++k)
            f.truth.corners[k] = project(f.frame.pose, Eigen::Vector3d(xs[k] * h * std::cos(a), ys[k] * h, -h * std::sin(a)));
          f.truth.black_square_px = mean_edge(f.truth.corners);
          break;
        }
        case Condition::kDistortion:
          for (auto& p : f.truth.corners) p = distort_pixel(p, -strength);
          f.truth.black_square_px = mean_edge(f.truth.corners);
          break;
        default: break;
      }
    }
    frames.push_back(std::move(f));
  };

  if (s.experiment == Experiment::kConditions) {
    for (const Condition c : s.conditions) {
      const auto& strengths = condition_info(c).strengths;
      for (std::size_t k = 0; k < strengths.size(); ++k)
        for (int t = 0; t < s.trials; ++t) {
          const Draw& d = draws[static_cast<std::size_t>(t)];
          const ViewSpec v{.distance = *s.distance, .phi_deg = d.phi, .tilt_axis_deg = d.tilt, .roll_deg = d.roll, .pixel = d.pixel};
          add(d, t, strengths[k], v, c, strengths[k], k);
        }
    }
  } else {
    for (const double step : s.steps)
      for (int t = 0; t < s.trials; ++t) {
        const Draw& d = draws[static_cast<std::size_t>(t)];
        ViewSpec v{.distance = 1, .phi_deg = 0, .tilt_axis_deg = d.tilt, .roll_deg = d.roll, .pixel = d.pixel};
        if (s.experiment == Experiment::kAngle) {
          v.distance = *s.distance;
          v.phi_deg = step;
        } else {
          v.distance = step;
        }
        add(d, t, step, v, Condition::kNone, 0, 0);
      }
  }
  return frames;
}

// ---- image effects -------------------------------------------------------------------------------------

cv::Mat apply_effect(const cv::Mat& gray8, const SweepFrame& f) {
  if (gray8.type() != CV_8UC1) throw std::invalid_argument("apply_effect needs an 8-bit gray image");
  const ImageEffect& e = f.effect;
  if (e.strength == 0) return gray8;
  cv::Mat out;
  switch (e.condition) {
    case Condition::kNoise: {
      out.create(gray8.size(), CV_8UC1);
      Rng rng{e.seed};
      for (int y = 0; y < gray8.rows; ++y)
        for (int x = 0; x < gray8.cols; ++x)
          out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(
              std::lround(gray8.at<std::uint8_t>(y, x) + e.strength * rng.normal()));
      return out;
    }
    case Condition::kBlur:
      cv::GaussianBlur(gray8, out, cv::Size(), e.strength, e.strength, cv::BORDER_REPLICATE);
      return out;
    case Condition::kGradient: {
      const Eigen::Vector2d u(std::cos(e.direction_deg * kDeg), std::sin(e.direction_deg * kDeg));
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& p : f.truth.corners) {
        lo = std::min(lo, p.dot(u));
        hi = std::max(hi, p.dot(u));
      }
      out.create(gray8.size(), CV_8UC1);
      for (int y = 0; y < gray8.rows; ++y)
        for (int x = 0; x < gray8.cols; ++x) {
          const double w = std::clamp((Eigen::Vector2d(x, y).dot(u) - lo) / (hi - lo), 0.0, 1.0);
          out.at<std::uint8_t>(y, x) =
              cv::saturate_cast<std::uint8_t>(std::lround(gray8.at<std::uint8_t>(y, x) * (1 - e.strength * w)));
        }
      return out;
    }
    case Condition::kDistortion: {
      const auto& [mx, my] = distortion_maps(-e.strength);
      cv::remap(gray8, out, mx, my, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
      return out;
    }
    default: return gray8;  // occlusion and bent are in the render
  }
}

// ---- the run -------------------------------------------------------------------------------------------

SweepResult run_sweep(const SweepSettings& settings, RenderOptions render_options, const SweepProgress& progress) {
  SweepResult res;
  res.settings = resolve_settings(settings);
  res.frames = plan_sweep(res.settings);
  const SweepSettings& s = res.settings;
  DetectorSet plain = make_detectors(s, std::nullopt);  // a bad detector setup fails before any rendering

  std::vector<FramePose> poses;
  poses.reserve(res.frames.size());
  for (const auto& f : res.frames) poses.push_back(f.frame);
  render_options.progress = progress.render;
  const RenderReport report = render_frames(poses, scene_template(s.scene), render_options);
  res.rendered = report.rendered;
  res.from_cache = report.from_cache;
  res.distinct_frames = report.rendered + report.from_cache + report.failed;
  res.povray_runs = report.povray_runs;
  res.render_seconds = report.seconds;
  for (std::size_t i = 0; i < res.frames.size(); ++i) {
    if (report.frames[i].ok()) continue;
    res.failed.push_back({i, report.frames[i].error});
    if (progress.failed) progress.failed(res.frames[i], report.frames[i].error);
  }
  if (!res.frames.empty() && res.failed.size() == res.frames.size())
    throw std::runtime_error("none of the " + std::to_string(res.frames.size()) +
                             " frames rendered: " + res.failed.front().error);

  const auto t0 = std::chrono::steady_clock::now();
  const int saved_threads = cv::getNumThreads();
  cv::setNumThreads(1);
  struct Restore {
    int n;
    ~Restore() { cv::setNumThreads(n); }
  } restore{saved_threads};
  std::map<double, DetectorSet> distorted;             // per k1
  std::map<std::string, std::vector<DetectorOutput>> plain_outputs;  // an unmodified frame runs once
  std::string gray_path;
  cv::Mat gray;
  const std::size_t total = res.frames.size() - res.failed.size();
  std::size_t done = 0;
  for (std::size_t i = 0; i < res.frames.size(); ++i) {
    if (!report.frames[i].ok()) continue;
    const SweepFrame& f = res.frames[i];
    const std::string png = report.frames[i].png.string();
    const bool unmodified = f.effect.strength == 0 || f.effect.condition == Condition::kOcclusion ||
                            f.effect.condition == Condition::kBent;
    std::vector<DetectorOutput>* outputs = nullptr;
    std::vector<DetectorOutput> fresh;
    if (unmodified) {
      if (auto it = plain_outputs.find(png); it != plain_outputs.end()) outputs = &it->second;
    }
    if (!outputs) {
      if (png != gray_path) {
        gray = read_frame_gray(png);
        gray_path = png;
      }
      const cv::Mat image = apply_effect(gray, f);
      DetectorSet* set = &plain;
      if (f.effect.condition == Condition::kDistortion && f.effect.strength != 0) {
        const double k1 = -f.effect.strength;
        auto it = distorted.find(k1);
        if (it == distorted.end()) it = distorted.emplace(k1, make_detectors(s, k1)).first;
        set = &it->second;
      }
      for (auto& det : *set) fresh.push_back(det->run(image));
      if (unmodified) outputs = &plain_outputs.emplace(png, std::move(fresh)).first->second;
      else outputs = &fresh;
    }
    for (std::size_t k = 0; k < s.detectors.size(); ++k) res.rows.push_back(row_of((*outputs)[k], s.detectors[k], i, f));
    ++done;
    if (progress.detect) progress.detect(done, total);
  }
  res.detect_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

// ---- summaries -----------------------------------------------------------------------------------------

double quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::vector<SummaryRow> summarize(const SweepResult& r) {
  struct Acc {
    SummaryRow row;
    std::vector<double> o, dm, dp, c, px, ms;
  };
  std::vector<Acc> groups;
  std::map<std::tuple<int, double, std::string>, std::size_t> index;
  for (const SweepRow& row : r.rows) {
    const SweepFrame& f = r.frames[row.frame];
    const auto key = std::make_tuple(static_cast<int>(f.condition), f.step, row.detector);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, groups.size()).first;
      Acc a;
      a.row.condition = f.condition;
      a.row.step = f.step;
      a.row.detector = row.detector;
      groups.push_back(std::move(a));
    }
    Acc& a = groups[it->second];
    ++a.row.frames;
    a.px.push_back(f.truth.black_square_px);
    a.ms.push_back(row.ms);
    if (row.wrong_id) ++a.row.wrong_id_frames;
    if (!row.detected_right_id) continue;
    ++a.row.detected;
    a.o.push_back(row.orientation_error_deg);
    a.dm.push_back(row.distance_error_m);
    a.dp.push_back(row.distance_error_percent);
    a.c.push_back(row.corner_rms_px);
  }
  std::vector<SummaryRow> out;
  const auto stats = [](const std::vector<double>& v) { return ErrorStats{quantile(v, 0.5), quantile(v, 0.1), quantile(v, 0.9)}; };
  for (Acc& a : groups) {
    SummaryRow& s = a.row;
    s.detection_rate = static_cast<double>(s.detected) / s.frames;
    const Interval ci = wilson_interval(static_cast<std::uint64_t>(s.detected), static_cast<std::uint64_t>(s.frames));
    s.rate_lo95 = ci.lo;
    s.rate_hi95 = ci.hi;
    s.black_square_px_median = quantile(a.px, 0.5);
    s.ms_median = quantile(a.ms, 0.5);
    s.orientation_deg = stats(a.o);
    s.distance_m = stats(a.dm);
    s.distance_percent = stats(a.dp);
    s.corner_rms_px = stats(a.c);
    out.push_back(s);
  }
  return out;
}

// ---- files ---------------------------------------------------------------------------------------------

std::string rows_csv(const SweepResult& r) {
  const SweepSettings& s = r.settings;
  std::string o =
      "experiment,condition,step,step_unit,trial,seed,id,scene,family,tag_size_m,distance_m,phi_deg,tilt_axis_deg,"
      "roll_deg,image_x,image_y,black_square_px,detector,detected_right_id,wrong_id,orientation_error_deg,"
      "distance_error_m,distance_error_percent,corner_rms_px,decision_margin,ms\n";
  for (const SweepRow& row : r.rows) {
    const SweepFrame& f = r.frames[row.frame];
    o += std::string(experiment_name(s.experiment)) + "," + condition_name(f.condition) + "," +
         format_cell(f.step, "%.10g") + "," + step_unit(f, s.experiment) + "," + std::to_string(f.trial) + "," +
         std::to_string(f.seed) + "," + std::to_string(f.frame.id) + "," + scene_name(s.scene) + "," + f.frame.family +
         "," + format_cell(f.frame.tag_size, "%.10g") + "," + format_cell(f.frame.pose.t.norm(), "%.10g") + "," +
         format_cell(view_angle_deg(f.frame.pose), "%.6f") + "," + format_cell(f.view.tilt_axis_deg, "%.6f") + "," +
         format_cell(f.view.roll_deg, "%.6f") + "," + format_cell(f.view.pixel.x(), "%.4f") + "," +
         format_cell(f.view.pixel.y(), "%.4f") + "," + format_cell(f.truth.black_square_px, "%.4f") + "," +
         row.detector + "," + (row.detected_right_id ? "1" : "0") + "," + (row.wrong_id ? "1" : "0") + "," +
         format_cell(row.orientation_error_deg, "%.6g") + "," + format_cell(row.distance_error_m, "%.6g") + "," +
         format_cell(row.distance_error_percent, "%.6g") + "," + format_cell(row.corner_rms_px, "%.6g") + "," +
         format_cell(row.decision_margin, "%.6g") + "," + format_cell(row.ms, "%.4f") + "\n";
  }
  return o;
}

std::string summary_csv(const SweepResult& r, const std::vector<SummaryRow>& summary) {
  std::string o =
      "experiment,condition,step,step_unit,detector,frames,detected,detection_rate,rate_lo95,rate_hi95,"
      "wrong_id_frames,black_square_px_median,"
      "orientation_error_deg_median,orientation_error_deg_p10,orientation_error_deg_p90,"
      "distance_error_m_median,distance_error_m_p10,distance_error_m_p90,"
      "distance_error_percent_median,distance_error_percent_p10,distance_error_percent_p90,"
      "corner_rms_px_median,corner_rms_px_p10,corner_rms_px_p90,ms_median\n";
  const auto st = [](const ErrorStats& e) {
    return format_cell(e.median, "%.6g") + "," + format_cell(e.p10, "%.6g") + "," + format_cell(e.p90, "%.6g");
  };
  for (const SummaryRow& s : summary) {
    SweepFrame probe;
    probe.condition = s.condition;
    o += std::string(experiment_name(r.settings.experiment)) + "," + condition_name(s.condition) + "," +
         format_cell(s.step, "%.10g") + "," + step_unit(probe, r.settings.experiment) + "," + s.detector + "," +
         std::to_string(s.frames) + "," + std::to_string(s.detected) + "," + format_cell(s.detection_rate, "%.6g") +
         "," + format_cell(s.rate_lo95, "%.6g") + "," + format_cell(s.rate_hi95, "%.6g") + "," +
         std::to_string(s.wrong_id_frames) + "," + format_cell(s.black_square_px_median, "%.4f") + "," +
         st(s.orientation_deg) + "," + st(s.distance_m) + "," + st(s.distance_percent) + "," + st(s.corner_rms_px) +
         "," + format_cell(s.ms_median, "%.4f") + "\n";
  }
  return o;
}

std::string sidecar_json(const SweepResult& r) {
  const SweepSettings& s = r.settings;
  const CameraIntrinsics K = render_camera();
  std::string j = "{\n  \"tool\": \"tagbench raytrace\",\n";
  j += "  \"experiment\": " + json_string(experiment_name(s.experiment)) + ",\n";
  const char* paper = s.experiment == Experiment::kAngle      ? "Fig. 9 (section VI-B)"
                      : s.experiment == Experiment::kDistance ? "Fig. 10 (section VI-B)"
                                                              : "beyond the paper";
  j += "  \"paper\": " + json_string(paper) + ",\n";
  j += "  \"files\": {\"rows\": " + json_string(std::string(result_stem(s.experiment)) + ".csv") +
       ", \"summary\": " + json_string(std::string(result_stem(s.experiment)) + "_summary.csv") + "},\n";
  j += "  \"settings\": {\"scene\": " + json_string(scene_name(s.scene)) + ", \"family\": " + json_string(s.family) +
       ", \"tag_size_m\": " + json_number(*s.tag_size) + ", \"seed\": " + std::to_string(s.seed) +
       ", \"trials\": " + std::to_string(s.trials) + ",\n    \"steps\": " +
       (s.experiment == Experiment::kConditions ? std::string("null") : json_numbers(s.steps)) +
       ", \"step_unit\": " +
       (s.experiment == Experiment::kAngle      ? json_string("deg")
        : s.experiment == Experiment::kDistance ? json_string("m")
                                                : std::string("null")) +
       ",\n    \"distance_m\": " + (s.distance ? json_number(*s.distance) : std::string("null")) +
       ", \"position_radius_px\": " + json_number(position_radius_px(s.experiment)) + ", \"phi_deg\": ";
  if (s.experiment == Experiment::kAngle) j += "\"the step\"";
  else if (s.experiment == Experiment::kDistance) j += "0";
  else
    j += "\"uniform in [0, " + format_cell(kConditionsMaxPhi, "%.10g") + "]\"";
  j += ",\n    \"detectors\": [";
  for (std::size_t i = 0; i < s.detectors.size(); ++i) j += (i ? ", " : "") + json_string(s.detectors[i]);
  j += "],\n    \"random\": " +
       json_string("per trial: splitmix64 seeded from (seed, experiment, trial) draws the id, the tilt axis and "
                   "the in-plane rotation (uniform in [0, 360) degrees), the image position (uniform in a disc of "
                   "position_radius_px about the principal point), and for conditions phi and the gradient's "
                   "direction; the same draws at every step") +
       "},\n";
  j += "  \"camera\": {\"width\": " + std::to_string(kRenderWidth) + ", \"height\": " + std::to_string(kRenderHeight) +
       ", \"fx\": " + json_number(K.fx) + ", \"fy\": " + json_number(K.fy) + ", \"cx\": " + json_number(K.cx) +
       ", \"cy\": " + json_number(K.cy) +
       ", \"renderer\": \"POV-Ray 3.7, +A0.1 +AM2 +R3, File_Gamma 1.0\", \"pixels\": \"centres at integer "
       "coordinates\"},\n";
  j += "  \"conditions\": [";
  if (s.experiment == Experiment::kConditions) {
    for (std::size_t i = 0; i < s.conditions.size(); ++i) {
      const auto& c = condition_info(s.conditions[i]);
      j += std::string(i ? "," : "") + "\n    {\"name\": " + json_string(c.name) + ", \"unit\": " + json_string(c.unit) +
           ", \"strengths\": " + json_numbers(c.strengths) + ",\n     \"description\": " + json_string(c.description) +
           "}";
    }
    j += "\n  ";
  }
  j += "],\n";
  j += "  \"measures\": " +
       json_string("detected_right_id: a detection with the frame's id; wrong_id: a detection with another id; "
                   "errors of the right-id detection nearest the truth: orientation = the angle of R_est^T R_true, "
                   "distance = | |t_est| - |t_true| | (m and % of |t_true|), corner RMS over the four corners (px); "
                   "ms: the detector's wall time on the frame, one thread; summaries: Wilson 95 % interval, "
                   "percentiles over the detected frames") +
       ",\n";
  j += "  \"frames\": " + std::to_string(r.frames.size()) + ", \"distinct_frames\": " +
       std::to_string(r.distinct_frames) + ", \"rendered\": " + std::to_string(r.rendered) +
       ", \"from_cache\": " + std::to_string(r.from_cache) + ", \"povray_runs\": " + std::to_string(r.povray_runs) +
       ",\n  \"render_seconds\": " + json_number(r.render_seconds) + ", \"detect_seconds\": " +
       json_number(r.detect_seconds) + ",\n";
  j += "  \"failed\": [";
  for (std::size_t i = 0; i < r.failed.size(); ++i) {
    const SweepFrame& f = r.frames[r.failed[i].frame];
    j += std::string(i ? "," : "") + "\n    {\"frame\": " + std::to_string(r.failed[i].frame) +
         ", \"condition\": " + json_string(condition_name(f.condition)) + ", \"step\": " + json_number(f.step) +
         ", \"trial\": " + std::to_string(f.trial) + ", \"error\": " + json_string(r.failed[i].error) + "}";
  }
  j += r.failed.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return j;
}

}  // namespace tagbench::bench
