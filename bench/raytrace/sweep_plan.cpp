// Settings (defaults, validation) and the plan of an experiment's frames: every trial's draws, the
// views, the ground truth, and what each condition adds to the render or the truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>

#include "codes/families.hpp"
#include "raytrace/sixdof.hpp"
#include "raytrace/sweep_detail.hpp"
#include "raytrace/sweeps.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

// ---- conditions ----------------------------------------------------------------------------------------

constexpr double kOccluderGrey = 0.35;

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
Eigen::Vector2d distort_pixel_k1(const Eigen::Vector2d& p, double k1) {
  const CameraIntrinsics K = render_camera();
  const double x = (p.x() - K.cx) / K.fx, y = (p.y() - K.cy) / K.fy, r2 = x * x + y * y;
  const double f = 1 + k1 * r2;
  return {K.fx * x * f + K.cx, K.fy * y * f + K.cy};
}

int tag_cells_across(const std::string& family) {
  const int bits = load_family(family).bits();
  const int d = static_cast<int>(std::lround(std::sqrt(static_cast<double>(bits))));
  return d + 4;
}

}  // namespace

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

const ExternalDetector* find_external(const SweepSettings& s, const std::string& name) {
  for (const auto& e : s.external)
    if (e.name == name) return &e;
  return nullptr;
}

namespace {

// sixdof's settings: no steps, conditions or fixed distance; its ranges and camera in range.
void resolve_sixdof(const SweepSettings& s, const std::string& what) {
  if (!s.steps.empty()) throw std::invalid_argument(what + "takes no steps (its frames are Halton samples)");
  if (s.distance) throw std::invalid_argument(what + "takes a distance range, not a fixed distance");
  const SixdofSettings& x = s.sixdof;
  const auto num = [](double v) { return format_cell(v, "%.10g"); };
  if (!(x.distance_min > 0) || !(x.distance_max >= x.distance_min) || !(x.distance_max <= kMaxSweepDistance))
    throw std::invalid_argument("distance range must be 0 < A <= B metres (got " + num(x.distance_min) + "," +
                                num(x.distance_max) + ")");
  if (!(x.phi_max_deg >= 0 && x.phi_max_deg < 90))
    throw std::invalid_argument("phi max " + num(x.phi_max_deg) + " is outside [0, 90) degrees");
  for (const double k : x.distortion)
    if (!std::isfinite(k) || std::abs(k) > 10) throw std::invalid_argument("lens coefficient " + num(k) + " is not in [-10, 10]");
  if (!(x.defocus_max_px >= 0 && x.defocus_max_px <= 50))
    throw std::invalid_argument("defocus max " + num(x.defocus_max_px) + " is outside [0, 50] px");
  if (!(x.noise_max >= 0 && x.noise_max <= 255))
    throw std::invalid_argument("noise max " + num(x.noise_max) + " is outside [0, 255] levels");
  if (!(x.margin_px >= 0 && x.margin_px < 100))
    throw std::invalid_argument("margin " + num(x.margin_px) + " is outside [0, 100) px");
  if (x.bins < 1 || x.bins > 100) throw std::invalid_argument("bins must be in 1..100 (got " + std::to_string(x.bins) + ")");
}

}  // namespace

SweepSettings resolve_settings(const SweepSettings& in) {
  SweepSettings s = in;
  const std::string what = std::string(experiment_name(s.experiment)) + " sweep: ";
  // Bounds far beyond any sweep, inside which the plan fits in memory (a frame's plan is some hundred
  // bytes; 1e9 trials ran out of it) and the renderer's arithmetic stays well scaled.
  const char* count = s.experiment == Experiment::kSixdof ? "frames" : "trials";
  if (s.trials <= 0 || s.trials > kMaxSweepTrials)
    throw std::invalid_argument(std::string(count) + " must be in 1.." + std::to_string(kMaxSweepTrials) + " (got " +
                                std::to_string(s.trials) + ")");
  if (!s.tag_size) s.tag_size = s.experiment == Experiment::kDistance ? 1.0 : 0.166;
  if (!(*s.tag_size >= 1e-3 && *s.tag_size <= 1e3))
    throw std::invalid_argument("tag size must be in [0.001, 1000] metres (got " + format_cell(*s.tag_size, "%.10g") + ")");
  const auto& known = comparator_names();
  for (const auto& e : s.external)
    if (std::find(known.begin(), known.end(), e.name) != known.end())
      throw std::invalid_argument("external detector '" + e.name + "': the name of a built-in detector");
  if (s.detectors.empty()) {
    s.detectors = known;
    for (const auto& e : s.external) s.detectors.push_back(e.name);
  }
  std::set<std::string> seen;
  for (const auto& d : s.detectors) {
    if (std::find(known.begin(), known.end(), d) == known.end() && !is_ours_variant(d) && !find_external(s, d)) {
      std::string list;
      for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown detector '" + d + "' (" + list + ", external:NAME=COMMAND)");
    }
    if (!seen.insert(d).second) throw std::invalid_argument("detector '" + d + "' given twice");
  }
  for (const auto& e : s.external)
    if (!seen.count(e.name)) throw std::invalid_argument("external detector '" + e.name + "' is not among the detectors");
  load_family(s.family);  // an unknown family fails here
  for (const auto& d : s.detectors) {  // and one a detector does not know ("libapriltag has no family ...")
    if (find_external(s, d)) continue;  // an external detector is told nothing of the family
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
  if (s.experiment == Experiment::kSixdof) {
    resolve_sixdof(s, what);
    return s;
  }
  if (s.experiment == Experiment::kDistance) {
    if (s.distance) throw std::invalid_argument(what + "its distances are its steps (not a fixed distance)");
  } else {
    if (!s.distance) s.distance = 1.0;
    if (!(*s.distance > 0 && *s.distance <= kMaxSweepDistance))
      throw std::invalid_argument("distance must be in (0, 1e6] metres (got " + format_cell(*s.distance, "%.10g") + ")");
  }
  if (s.experiment != Experiment::kConditions) {
    if (s.steps.empty()) s.steps = default_steps(s.experiment);
    std::set<double> steps;
    for (const double v : s.steps) {
      if (s.experiment == Experiment::kAngle && !(v >= 0 && v < 90))
        throw std::invalid_argument("angle " + format_cell(v, "%.10g") + " is outside [0, 90) degrees");
      if (s.experiment == Experiment::kDistance && !(v > 0 && v <= kMaxSweepDistance))
        throw std::invalid_argument("distance must be in (0, 1e6] metres (got " + format_cell(v, "%.10g") + ")");
      if (!steps.insert(v).second) throw std::invalid_argument("step " + format_cell(v, "%.10g") + " given twice");
    }
  }
  return s;
}

double view_angle_deg(const Pose& pose) {
  const Eigen::Vector3d normal = -pose.R.col(2), to_camera = -pose.t.normalized();
  return std::atan2(normal.cross(to_camera).norm(), normal.dot(to_camera)) / kDeg;  // exact near 0 too
}

bool frame_unmodified(const SweepFrame& f) {
  if (f.effect.camera) return false;
  return f.effect.strength == 0 || f.effect.condition == Condition::kOcclusion || f.effect.condition == Condition::kBent;
}

std::vector<SweepFrame> plan_sweep(const SweepSettings& in) {
  const SweepSettings s = resolve_settings(in);
  if (s.experiment == Experiment::kSixdof) return plan_sixdof(s);
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
    f.frame.family_name = family.name();
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
          for (auto& p : f.truth.corners) p = distort_pixel_k1(p, -strength);
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

}  // namespace tagbench::bench
