// The localization sweeps' plans (issue 4, section 2), nothing rendered: the plans put every frame
// where its step says (phi from the pose, 1/distance pixel widths, the same random draws at every
// step), bad settings are refused, the image effects do what they claim, another family has its own
// result stem, and the quantiles. The sweeps run on ray-traced frames in test_sweep_runs.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "raytrace/sweeps.hpp"
#include "plan_refusal.hpp"

namespace test_sweep_plans {

using namespace tagbench;
using namespace tagbench::bench;
using test::refusal;
using test::settings;

// ---- plans (no rendering) ------------------------------------------------------------------------------

TEST(SweepPlan, AngleFramesHaveTheRequestedPhiAtTheFixedDistanceWithTheSameDrawsAtEveryStep) {
  const auto frames = plan_sweep(settings(Experiment::kAngle, 4));
  ASSERT_EQ(frames.size(), 18u * 4);
  const CameraIntrinsics K = render_camera();
  std::map<int, const SweepFrame*> first_of_trial;
  std::set<int> ids;
  for (const auto& f : frames) {
    // phi from the pose itself: the angle between the tag's normal and the direction to the camera.
    const Eigen::Vector3d normal = -f.frame.pose.R.col(2), to_camera = -f.frame.pose.t.normalized();
    const double phi = std::acos(std::clamp(normal.dot(to_camera), -1.0, 1.0)) * 180 / M_PI;
    EXPECT_NEAR(phi, f.step, 1e-5) << "trial " << f.trial;  // acos near 1: ~1e-6 degrees of rounding
    EXPECT_NEAR(view_angle_deg(f.frame.pose), f.step, 1e-9);
    EXPECT_NEAR(f.frame.pose.t.norm(), 1.0, 1e-12);
    EXPECT_NEAR(f.frame.tag_size, 0.166, 0);
    EXPECT_EQ(f.frame.family, "36h11");
    EXPECT_TRUE(f.frame.extra_sdl.empty());
    EXPECT_EQ(f.effect.condition, Condition::kNone);
    // The tag centre is where the view puts it, within the position radius.
    const Eigen::Vector3d& t = f.frame.pose.t;
    const Eigen::Vector2d centre(K.fx * t.x() / t.z() + K.cx, K.fy * t.y() / t.z() + K.cy);
    EXPECT_LT((centre - f.view.pixel).norm(), 1e-9);
    EXPECT_LE((f.view.pixel - Eigen::Vector2d(K.cx, K.cy)).norm(), 100 + 1e-9);
    // The whole printed tag is in the image.
    FramePose whole = f.frame;
    whole.tag_size *= 10.0 / 8;
    for (const auto& c : ground_truth(whole).corners) {
      EXPECT_GE(c.x(), 0);
      EXPECT_LE(c.x(), 399);
      EXPECT_GE(c.y(), 0);
      EXPECT_LE(c.y(), 399);
    }
    auto [it, fresh] = first_of_trial.emplace(f.trial, &f);
    if (!fresh) {  // the same draws at every step
      EXPECT_EQ(f.seed, it->second->seed);
      EXPECT_EQ(f.frame.id, it->second->frame.id);
      EXPECT_EQ(f.view.roll_deg, it->second->view.roll_deg);
      EXPECT_EQ(f.view.tilt_axis_deg, it->second->view.tilt_axis_deg);
      EXPECT_EQ(f.view.pixel, it->second->view.pixel);
    }
    ids.insert(f.frame.id);
  }
  EXPECT_EQ(ids.size(), 4u) << "each trial its own random id";
  std::set<std::uint64_t> seeds;
  for (const auto& [trial, f] : first_of_trial) seeds.insert(f->seed);
  EXPECT_EQ(seeds.size(), 4u);
  // Face-on at 1 m the default black square is 400 * 0.166 = 66.4 px wide; off the centre the tag is
  // nearer in depth (1 m along the ray), so up to 1 / cos(atan(100 / 400)) = 3 % more, and a little
  // more from the perspective of a tag turned toward the camera.
  for (const auto& f : frames) {
    if (f.step != 0) continue;
    EXPECT_GE(f.truth.black_square_px, 66.4 - 1e-9);
    EXPECT_LE(f.truth.black_square_px, 66.4 * 1.06);
  }
}

TEST(SweepPlan, DistanceFramesAreFaceOnAndTheBlackSquareShrinksAsOneOverDistance) {
  const auto frames = plan_sweep(settings(Experiment::kDistance, 3));
  const auto steps = default_steps(Experiment::kDistance);
  ASSERT_EQ(frames.size(), steps.size() * 3);
  EXPECT_EQ(steps.front(), 2);
  EXPECT_EQ(steps.back(), 60);
  std::map<int, double> product;  // black square px x distance, per trial
  for (const auto& f : frames) {
    EXPECT_NEAR(view_angle_deg(f.frame.pose), 0, 1e-6);
    EXPECT_NEAR(f.frame.pose.t.norm(), f.step, 1e-9);
    EXPECT_EQ(f.frame.tag_size, 1.0);
    // 400 px x 1 m / d, off the centre by at most 20 px: within 0.5 %.
    EXPECT_NEAR(f.truth.black_square_px * f.step / 400, 1, 0.005) << f.step;
    auto [it, fresh] = product.emplace(f.trial, f.truth.black_square_px * f.step);
    if (!fresh) {  // the same trial at another distance: the same width x distance, to perspective's 1e-4
      EXPECT_NEAR(f.truth.black_square_px * f.step, it->second, 5e-4 * it->second) << f.step;
    }
  }
  // Enough steps to see a detector fall off: 1 m apart to 10 m, 2.5 m apart to 60 m.
  for (std::size_t i = 1; i < steps.size(); ++i) EXPECT_LE(steps[i] - steps[i - 1], 2.5);
}

TEST(SweepPlan, IdenticalSeedsGiveIdenticalFramesAndAFrameDoesNotDependOnTheOtherSteps) {
  auto a = plan_sweep(settings(Experiment::kAngle, 3));
  auto b = plan_sweep(settings(Experiment::kAngle, 3));
  const auto& plain = scene_template(SceneKind::kPlain);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(frame_cache_key(a[i].frame, plain), frame_cache_key(b[i].frame, plain));
  // A subset of steps and trials: the same frames as in the full plan.
  const auto sub = plan_sweep(settings(Experiment::kAngle, 2, {30}));
  ASSERT_EQ(sub.size(), 2u);
  for (const auto& f : sub) {
    const auto it = std::find_if(a.begin(), a.end(), [&](const SweepFrame& g) { return g.step == 30 && g.trial == f.trial; });
    ASSERT_NE(it, a.end());
    EXPECT_EQ(frame_cache_key(f.frame, plain), frame_cache_key(it->frame, plain));
  }
  SweepSettings other = settings(Experiment::kAngle, 3);
  other.seed = 2;
  const auto c = plan_sweep(other);
  int same = 0;
  for (std::size_t i = 0; i < a.size(); ++i) same += frame_cache_key(a[i].frame, plain) == frame_cache_key(c[i].frame, plain);
  EXPECT_EQ(same, 0) << "another seed, other frames";
}

TEST(SweepPlan, BadSettingsAreRefusedWithOneLine) {
  const auto expect = [](const SweepSettings& s, const std::string& fragment) {
    const std::string msg = refusal(s);
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  };
  expect(settings(Experiment::kAngle, 0), "trials must be in 1..1000000");
  expect(settings(Experiment::kAngle, -3), "trials must be in 1..1000000");
  expect(settings(Experiment::kAngle, 1000000000), "trials must be in 1..1000000 (got 1000000000)");  // memory
  expect(settings(Experiment::kAngle, 1, {90}), "angle 90 is outside [0, 90) degrees");
  expect(settings(Experiment::kAngle, 1, {-1}), "angle -1 is outside [0, 90) degrees");
  expect(settings(Experiment::kAngle, 1, {10, 10}), "given twice");
  expect(settings(Experiment::kDistance, 1, {0}), "distance must be in (0, 1e6] metres");
  expect(settings(Experiment::kDistance, 1, {-5}), "distance must be in (0, 1e6] metres");
  expect(settings(Experiment::kDistance, 1, {1e300}), "distance must be in (0, 1e6] metres");
  SweepSettings s = settings(Experiment::kAngle, 1);
  s.distance = 0;
  expect(s, "distance must be in (0, 1e6] metres");
  s = settings(Experiment::kAngle, 1);
  s.tag_size = 0;
  expect(s, "tag size must be in [0.001, 1000] metres");
  s.tag_size = 1e-9;
  expect(s, "tag size must be in [0.001, 1000] metres");
  s = settings(Experiment::kAngle, 1);
  s.detectors = {"tagbench-paper", "zbar"};
  expect(s, "unknown detector 'zbar'");
  s.detectors = {"aruco", "aruco"};
  expect(s, "given twice");
  expect(settings(Experiment::kConditions, 1, {1}), "takes no steps");
  s = settings(Experiment::kDistance, 1);
  s.distance = 3;
  expect(s, "its distances are its steps");
  s = settings(Experiment::kDistance, 1);
  s.family = "36h99";
  expect(s, "unknown family '36h99'");
  s.family = "36h15";  // ours knows it, libapriltag does not
  expect(s, "libapriltag has no family");
  s.detectors = {"tagbench-paper"};
  EXPECT_EQ(resolve_settings(s).family, "36h15");
  s.family = "16h5";
  s.detectors = {};
  EXPECT_EQ(resolve_settings(s).detectors, comparator_names());  // all five know 16h5
  // A tag that cannot be wholly in view: a 1 m tag at 1 m (its black square would fill the image).
  expect(settings(Experiment::kDistance, 1, {1}), "does not fit");
  s = settings(Experiment::kAngle, 1);
  s.tag_size = 1;
  expect(s, "does not fit");
  EXPECT_THROW(parse_scene("studio"), std::invalid_argument);
  EXPECT_THROW(parse_condition("fog"), std::invalid_argument);
  EXPECT_THROW(parse_experiment("height"), std::invalid_argument);
  EXPECT_EQ(parse_scene("realistic"), SceneKind::kRealistic);
}

TEST(SweepPlan, ConditionsAtZeroStrengthAreThePlainFrames) {
  SweepSettings s = settings(Experiment::kConditions, 2);
  const auto frames = plan_sweep(s);
  ASSERT_EQ(frames.size(), 6u * 5 * 2);
  const auto& plain = scene_template(SceneKind::kPlain);
  std::map<int, std::string> base_key;  // per trial
  for (const auto& f : frames) {
    if (f.step != 0) continue;
    EXPECT_TRUE(f.frame.extra_sdl.empty());
    EXPECT_EQ(f.effect.condition, Condition::kNone);
    const std::string key = frame_cache_key(f.frame, plain);
    auto [it, fresh] = base_key.emplace(f.trial, key);
    EXPECT_EQ(key, it->second) << condition_name(f.condition) << ": the zero strength is one frame for all";
    EXPECT_LE(view_angle_deg(f.frame.pose), 30);
  }
  ASSERT_EQ(base_key.size(), 2u);
  for (const auto& f : frames) {
    if (f.step == 0) continue;
    const std::string key = frame_cache_key(f.frame, plain);
    const bool rendered = f.condition == Condition::kOcclusion || f.condition == Condition::kBent;
    EXPECT_EQ(key == base_key[f.trial], !rendered) << condition_name(f.condition) << " " << f.step
                                                   << ": image-space conditions reuse the plain render";
    EXPECT_EQ(f.frame.extra_sdl.empty(), !rendered);
    EXPECT_EQ(f.effect.condition, f.condition);
  }
}

// ---- image effects and statistics ---------------------------------------------------------------------

TEST(SweepEffects, NoiseBlurGradientAndDistortionDoWhatTheySay) {
  SweepFrame f = plan_sweep(settings(Experiment::kConditions, 1))[0];
  const cv::Mat grey(400, 400, CV_8UC1, cv::Scalar(128));
  f.effect = {Condition::kNoise, 16, 99, 0, std::nullopt};
  const cv::Mat noisy = apply_effect(grey, f);
  cv::Scalar mean, sd;
  cv::meanStdDev(noisy, mean, sd);
  EXPECT_NEAR(mean[0], 128, 0.3);
  EXPECT_NEAR(sd[0], 16, 0.5);
  EXPECT_EQ(cv::norm(noisy, apply_effect(grey, f), cv::NORM_INF), 0) << "seeded";
  f.effect.seed = 100;
  EXPECT_GT(cv::norm(noisy, apply_effect(grey, f), cv::NORM_INF), 0);

  cv::Mat step(400, 400, CV_8UC1, cv::Scalar(0));
  step.colRange(200, 400).setTo(255);
  f.effect = {Condition::kBlur, 2, 0, 0, std::nullopt};
  const cv::Mat blurred = apply_effect(step, f);
  EXPECT_EQ(blurred.at<std::uint8_t>(200, 100), 0);
  EXPECT_NEAR(blurred.at<std::uint8_t>(200, 199), 255 * 0.40, 4);  // Phi(-0.25) for sigma 2, half a pixel off
  EXPECT_NEAR(blurred.at<std::uint8_t>(200, 200), 255 * 0.60, 4);

  const cv::Mat white(400, 400, CV_8UC1, cv::Scalar(200));
  f.effect = {Condition::kGradient, 0.75, 0, 0, std::nullopt};  // light falls off toward +x across the black square
  const cv::Mat lit = apply_effect(white, f);
  double lo_x = 1e9, hi_x = -1e9;
  for (const auto& c : f.truth.corners) {
    lo_x = std::min(lo_x, c.x());
    hi_x = std::max(hi_x, c.x());
  }
  EXPECT_EQ(lit.at<std::uint8_t>(10, static_cast<int>(std::floor(lo_x)) - 1), 200);
  EXPECT_EQ(lit.at<std::uint8_t>(10, static_cast<int>(std::ceil(hi_x)) + 1), 50);
  EXPECT_NEAR(lit.at<std::uint8_t>(10, static_cast<int>(std::lround((lo_x + hi_x) / 2))), 200 * (1 - 0.375), 2);

  // Distortion: a dot at an undistorted pixel appears where the forward model puts it.
  cv::Mat dot(400, 400, CV_8UC1, cv::Scalar(0));
  cv::circle(dot, cv::Point(330, 90), 3, cv::Scalar(255), cv::FILLED);
  f.effect = {Condition::kDistortion, 0.3, 0, 0, std::nullopt};
  const cv::Mat warped = apply_effect(dot, f);
  const cv::Moments m = cv::moments(warped);
  const double x = (330 - 199.5) / 400, y = (90 - 199.5) / 400, k = 1 - 0.3 * (x * x + y * y);
  EXPECT_NEAR(m.m10 / m.m00, 199.5 + 400 * x * k, 0.1);
  EXPECT_NEAR(m.m01 / m.m00, 199.5 + 400 * y * k, 0.1);
  EXPECT_LT(m.m10 / m.m00, 329) << "barrel: toward the centre";
  f.effect = {Condition::kDistortion, 0, 0, 0, std::nullopt};
  EXPECT_EQ(cv::norm(apply_effect(dot, f), dot, cv::NORM_INF), 0) << "zero strength: the frame itself";
}

TEST(SweepNames, AnotherFamilyThan36h11IsInTheStemSoThatItDoesNotOverwriteThePapersFigures) {
  SweepSettings s;
  s.experiment = Experiment::kDistance;
  EXPECT_EQ(result_stem(s), "fig10_distance");
  s.family = "tag36h11";  // AprilTag's spelling of the same family
  EXPECT_EQ(result_stem(s), "fig10_distance");
  s.family = "16h5";
  EXPECT_EQ(result_stem(s), "fig10_distance_16h5");
  s.family = "tag25h9";
  s.experiment = Experiment::kAngle;
  EXPECT_EQ(result_stem(s), "fig9_angle_25h9");
  s.family = "/some/dir/my family.v2.fam";  // a family file: its name without extension, made file-safe
  s.experiment = Experiment::kConditions;
  EXPECT_EQ(result_stem(s), "conditions_my_family_v2");
}

TEST(SweepPlan, AFamilyFilesTagIsScoredByTheNameDetectorsReport) {
  // A family file's frames carry its path (to render it) and its own name (what detections say):
  // a detection of that name and id is the right id, not a wrong one.
  const std::filesystem::path f = std::filesystem::temp_directory_path() / "tagbench-sweep-family.fam";
  std::ofstream(f) << "name: my16\nbits: 16\nhamming: 5\ncomplexity: 0\ncount: 2\n0x231b\n0x2ea5\n";
  SweepSettings s;
  s.experiment = Experiment::kDistance;
  s.family = f.string();
  s.trials = 1;
  s.steps = {3};
  s.detectors = {comparator_names().front()};
  const std::vector<SweepFrame> plan = plan_sweep(s);
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_EQ(plan[0].frame.family, f.string());
  EXPECT_EQ(plan[0].frame.family_name, "my16");
  Found right;
  right.family = "my16";
  right.id = plan[0].frame.id;
  right.corners = plan[0].truth.corners;
  EXPECT_TRUE(score_frame(std::span(&right, 1), 1.0, "x", 0, plan[0]).detected_right_id);
  Found other = right;
  other.family = "16h5";
  EXPECT_TRUE(score_frame(std::span(&other, 1), 1.0, "x", 0, plan[0]).wrong_id);
  std::filesystem::remove(f);
}

TEST(SweepStats, Quantiles) {
  EXPECT_EQ(quantile({4, 1, 3, 2}, 0.5), 2.5);
  EXPECT_NEAR(quantile({4, 1, 3, 2}, 0.1), 1.3, 1e-12);
  EXPECT_NEAR(quantile({4, 1, 3, 2, NAN}, 0.9), 3.7, 1e-12);
  EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
}

}  // namespace test_sweep_plans
