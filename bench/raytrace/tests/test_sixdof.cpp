// The 6-DoF sweep (issue 12, section 4): the Halton unit, the plan (every variable in range, the whole
// tag in view, frames independent of how many are asked for), the camera (the lens warp puts a known
// point where cv::projectPoints says; defocus, noise and quantization), and a small run whose rows are
// reproducible and whose truth our detector matches to a fraction of a pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "raytrace/halton.hpp"
#include "raytrace/sixdof.hpp"
#include "raytrace/sweeps.hpp"
#include "plan_refusal.hpp"
#include "test_frames.hpp"

namespace test_sixdof {

using namespace tagbench;
using namespace tagbench::bench;

namespace {

SweepSettings sixdof(int frames) {
  SweepSettings s;
  s.experiment = Experiment::kSixdof;
  s.trials = frames;
  return s;
}

using test::refusal;

// The index of the interval of width 1/n that x falls in (the plain sequence's points sit on the
// intervals' left edges, where x * n may round just below the integer).
int cell(double x, int n) { return std::min(n - 1, static_cast<int>(std::floor(x * n + 1e-9))); }

}  // namespace

TEST(Halton, PrimesAndRadicalInverses) {
  EXPECT_EQ(first_primes(8), (std::vector<int>{2, 3, 5, 7, 11, 13, 17, 19}));
  EXPECT_DOUBLE_EQ(radical_inverse(0, 2), 0);
  EXPECT_DOUBLE_EQ(radical_inverse(1, 2), 0.5);
  EXPECT_DOUBLE_EQ(radical_inverse(2, 2), 0.25);
  EXPECT_DOUBLE_EQ(radical_inverse(3, 2), 0.75);
  EXPECT_DOUBLE_EQ(radical_inverse(6, 2), 0.375);  // 110 -> 0.011
  EXPECT_DOUBLE_EQ(radical_inverse(1, 3), 1.0 / 3);
  EXPECT_DOUBLE_EQ(radical_inverse(3, 3), 1.0 / 9);
  EXPECT_DOUBLE_EQ(radical_inverse(5, 3), 2.0 / 3 + 1.0 / 9);  // 12 -> 0.21
  const Halton plain(6, 0);  // seed 0: the unscrambled sequence
  for (std::uint64_t i = 0; i < 200; ++i)
    for (std::size_t d = 0; d < 6; ++d) EXPECT_DOUBLE_EQ(plain.coordinate(i, d), radical_inverse(i, plain.base(d)));
}

TEST(Halton, ScrambledPointsStratifyLikeThePlainOnes) {
  for (const std::uint64_t seed : {0ULL, 1ULL, 12345ULL}) {
    const Halton h(8, seed);
    // One dimension: the first b^k points fall one into each interval of width b^-k.
    for (std::size_t d = 0; d < 8; ++d) {
      const int b = h.base(d);
      const int n = b <= 5 ? b * b * b : b * b;
      std::set<int> cells;
      for (int i = 0; i < n; ++i) {
        const double x = h.coordinate(static_cast<std::uint64_t>(i), d);
        ASSERT_GE(x, 0);
        ASSERT_LT(x, 1);
        cells.insert(cell(x, n));
      }
      EXPECT_EQ(cells.size(), static_cast<std::size_t>(n)) << "seed " << seed << " base " << b;
    }
    // Two dimensions: the first 8 * 9 points of bases 2 and 3 fall one into each cell of the 8 x 9 grid.
    std::set<std::pair<int, int>> grid;
    for (std::uint64_t i = 0; i < 72; ++i) grid.insert({cell(h.coordinate(i, 0), 8), cell(h.coordinate(i, 1), 9)});
    EXPECT_EQ(grid.size(), 72u) << "seed " << seed;
  }
}

TEST(Halton, TheSeedScramblesReproducibly) {
  const Halton a(8, 7), b(8, 7), c(8, 8), plain(8, 0);
  int differ = 0;
  for (std::uint64_t i = 1; i < 50; ++i) {
    EXPECT_EQ(a.point(i), b.point(i));
    differ += a.point(i) != c.point(i);
    differ += a.point(i) != plain.point(i);
  }
  EXPECT_EQ(differ, 98);
  // The scramble breaks the plain sequence's correlation of bases 11 and 13: its points 1..10 are
  // (i / 11, i / 13), on one line.
  const auto corr = [](const Halton& h) {
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    const int n = 10;
    for (int i = 1; i <= n; ++i) {
      const double x = h.coordinate(static_cast<std::uint64_t>(i), 4), y = h.coordinate(static_cast<std::uint64_t>(i), 5);
      sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
    }
    return (sxy / n - sx / n * sy / n) / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  };
  EXPECT_GT(corr(plain), 0.999);
  EXPECT_LT(std::abs(corr(a)), 0.9);
  EXPECT_LT(std::abs(corr(Halton(8, 1))), 0.9);
  EXPECT_THROW(Halton(0, 1), std::invalid_argument);
}

TEST(SixdofLens, DistortAndUndistortAreInversesAndProjectPointsGivesTheCorners) {
  const std::array<double, 5> lens{-0.2, 0.05, 0.001, -0.0005, 0};
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(199.5, 199.5), Eigen::Vector2d(10, 20), Eigen::Vector2d(390, 300)}) {
    const Eigen::Vector2d q = distort_pixel(p, lens);
    const auto back = undistort_pixel(q, lens);
    ASSERT_TRUE(back.has_value());
    EXPECT_LT((*back - p).norm(), 1e-6);
  }
  // Barrel: a point off the centre moves toward it.
  EXPECT_LT((distort_pixel({380, 380}, lens) - Eigen::Vector2d(199.5, 199.5)).norm(), std::hypot(180.5, 180.5) - 5);
  // No lens: projectPoints' corners are the pinhole ground truth's.
  FramePose f;
  f.pose = view_pose({.distance = 1.2, .phi_deg = 35, .tilt_axis_deg = 70, .roll_deg = 20, .pixel = {150, 260}});
  const Corners pin = ground_truth(f).corners, cv_corners = project_corners(f.pose, f.tag_size, {});
  for (std::size_t k = 0; k < 4; ++k) EXPECT_LT((pin[k] - cv_corners[k]).norm(), 1e-9);
  // With the lens: each corner is the pinhole corner distorted.
  const Corners d = project_corners(f.pose, f.tag_size, lens);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_LT((d[k] - distort_pixel(pin[k], lens)).norm(), 1e-9);
}

TEST(SixdofCamera, TheLensWarpPutsAKnownPointWhereProjectPointsSays) {
  // Small bright blobs at known pinhole positions; after the warp each blob's centroid is at the point
  // distorted, to a few hundredths of a pixel (the residual is the blob's own distortion).
  const std::array<double, 5> lens{-0.2, 0.05, 0.001, -0.0005, 0};
  const std::vector<Eigen::Vector2d> points{{199.5, 199.5}, {80.3, 120.7}, {320.25, 90.5}, {300.8, 330.1}, {60.6, 340.2}};
  cv::Mat pinhole(kRenderHeight, kRenderWidth, CV_8UC1);
  for (int y = 0; y < pinhole.rows; ++y)
    for (int x = 0; x < pinhole.cols; ++x) {
      double v = 20;
      for (const auto& p : points) v += 200 * std::exp(-((x - p.x()) * (x - p.x()) + (y - p.y()) * (y - p.y())) / (2 * 1.2 * 1.2));
      pinhole.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(std::lround(v));
    }
  CameraEffects cam;
  cam.distortion = lens;
  const cv::Mat out = apply_camera_effects(pinhole, cam);
  for (const auto& p : points) {
    const Eigen::Vector2d q = distort_pixel(p, lens);
    double sw = 0, sx = 0, sy = 0;
    for (int y = static_cast<int>(q.y()) - 6; y <= static_cast<int>(q.y()) + 6; ++y)
      for (int x = static_cast<int>(q.x()) - 6; x <= static_cast<int>(q.x()) + 6; ++x) {
        const double w = std::max(0, out.at<std::uint8_t>(y, x) - 20);
        sw += w, sx += w * x, sy += w * y;
      }
    EXPECT_LT((Eigen::Vector2d(sx / sw, sy / sw) - q).norm(), 0.05) << p.transpose();
    if (p.x() != 199.5) {
      EXPECT_GT((q - p).norm(), 2.0);  // the lens moved it: the test could fail
    }
  }
}

TEST(SixdofCamera, DefocusNoiseAndQuantizationDoWhatTheySay) {
  cv::Mat edge(100, 100, CV_8UC1, cv::Scalar(40));
  edge.colRange(50, 100).setTo(200);
  CameraEffects none;
  EXPECT_EQ(cv::norm(apply_camera_effects(edge, none), edge, cv::NORM_INF), 0);  // the identity
  CameraEffects blur;
  blur.defocus_sigma_px = 2;
  const cv::Mat b = apply_camera_effects(edge, blur);
  EXPECT_GT(b.at<std::uint8_t>(50, 48), 45);
  EXPECT_LT(b.at<std::uint8_t>(50, 51), 195);
  CameraEffects noise;
  noise.noise_sigma = 5;
  noise.noise_seed = 3;
  const cv::Mat n1 = apply_camera_effects(edge, noise), n2 = apply_camera_effects(edge, noise);
  EXPECT_EQ(cv::norm(n1, n2, cv::NORM_INF), 0);  // seeded
  cv::Mat diff;
  cv::Mat(n1(cv::Rect(0, 0, 40, 100))).convertTo(diff, CV_64F, 1, -40);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd);
  EXPECT_NEAR(sd[0], 5, 0.3);
  EXPECT_NEAR(mean[0], 0, 0.3);
  CameraEffects four_bits;
  four_bits.quantization_bits = 4;  // 16 levels, 17 apart
  const cv::Mat q = apply_camera_effects(edge, four_bits);
  EXPECT_EQ(q.at<std::uint8_t>(0, 0), 34);
  EXPECT_EQ(q.at<std::uint8_t>(0, 99), 204);
}

TEST(SixdofPlan, EveryVariableIsInRangeAndTheWholeTagIsInView) {
  SweepSettings s = sixdof(60);
  const std::vector<SweepFrame> frames = plan_sweep(s);
  ASSERT_EQ(frames.size(), 60u);
  const SweepSettings r = resolve_settings(s);
  const auto vars = sixdof_variables(r);
  ASSERT_EQ(vars.size(), 8u);
  const double printed = 0.166 * 10 / 8;  // 36h11: 6 data cells, the black ring, the white ring
  std::set<int> ids;
  std::uint64_t last = 0;
  for (const SweepFrame& f : frames) {
    for (std::size_t v = 0; v < vars.size(); ++v) {
      EXPECT_GE(sixdof_value(f, v), vars[v].lo) << vars[v].name;
      EXPECT_LE(sixdof_value(f, v), vars[v].hi) << vars[v].name;
    }
    EXPECT_GT(f.sample, last);  // Halton order
    last = f.sample;
    EXPECT_NEAR(view_angle_deg(f.frame.pose), f.view.phi_deg, 1e-6);
    EXPECT_NEAR(f.frame.pose.t.norm(), f.view.distance, 1e-9);
    ASSERT_TRUE(f.effect.camera.has_value());
    EXPECT_EQ(f.effect.camera->distortion, r.sixdof.distortion);
    EXPECT_LT((distort_pixel(f.view.pixel, r.sixdof.distortion) - f.image_position).norm(), 1e-6);
    // The whole printed tag inside the image, through the lens and in the pinhole render.
    for (const auto& lens : {r.sixdof.distortion, std::array<double, 5>{}})
      for (const auto& p : project_corners(f.frame.pose, printed, lens)) {
        EXPECT_GE(p.x(), 2);
        EXPECT_LE(p.x(), kRenderWidth - 3);
        EXPECT_GE(p.y(), 2);
        EXPECT_LE(p.y(), kRenderHeight - 3);
      }
    const Corners truth = project_corners(f.frame.pose, 0.166, r.sixdof.distortion);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(f.truth.corners[k], truth[k]);
    ids.insert(f.frame.id);
  }
  EXPECT_GT(ids.size(), 50u);  // random ids
  // Some points were skipped (close tags near the edge do not fit), and the kept ones still cover the range.
  EXPECT_GT(frames.back().sample, 60u);
  EXPECT_LT(std::min_element(frames.begin(), frames.end(), [](auto& a, auto& b) { return a.view.distance < b.view.distance; })->view.distance, 1.0);
  EXPECT_GT(std::max_element(frames.begin(), frames.end(), [](auto& a, auto& b) { return a.view.distance < b.view.distance; })->view.distance, 5.5);
}

TEST(SixdofPlan, AFrameDoesNotDependOnHowManyAreAskedForAndTheSeedChangesThem) {
  const auto few = plan_sweep(sixdof(5)), more = plan_sweep(sixdof(12));
  for (std::size_t i = 0; i < few.size(); ++i) {
    EXPECT_EQ(few[i].sample, more[i].sample);
    EXPECT_EQ(few[i].frame.pose.R, more[i].frame.pose.R);
    EXPECT_EQ(few[i].frame.id, more[i].frame.id);
    EXPECT_EQ(few[i].effect.camera->noise_seed, more[i].effect.camera->noise_seed);
  }
  SweepSettings other = sixdof(5);
  other.seed = 2;
  EXPECT_NE(plan_sweep(other)[0].view.distance, few[0].view.distance);
}

TEST(SixdofPlan, BadSettingsAreRefusedWithOneLine) {
  SweepSettings s = sixdof(3);
  s.sixdof.distance_min = 0;
  EXPECT_EQ(refusal(s), "distance range must be 0 < A <= B metres (got 0,6)");
  s = sixdof(3);
  s.sixdof.distance_min = 3, s.sixdof.distance_max = 2;
  EXPECT_EQ(refusal(s), "distance range must be 0 < A <= B metres (got 3,2)");
  s = sixdof(3);
  s.sixdof.phi_max_deg = 90;
  EXPECT_EQ(refusal(s), "phi max 90 is outside [0, 90) degrees");
  s = sixdof(3);
  s.sixdof.bins = 0;
  EXPECT_EQ(refusal(s), "bins must be in 1..100 (got 0)");
  s = sixdof(3);
  s.steps = {1};
  EXPECT_EQ(refusal(s), "sixdof sweep: takes no steps (its frames are Halton samples)");
  s = sixdof(3);
  s.distance = 1;
  EXPECT_EQ(refusal(s), "sixdof sweep: takes a distance range, not a fixed distance");
  s = sixdof(3);
  s.sixdof.distance_min = s.sixdof.distance_max = 0.1;  // a 0.2 m printed tag never fits at 0.1 m
  EXPECT_NE(refusal(s).find("the tag does not fit in the 400 x 400 image"), std::string::npos) << refusal(s);
  s = sixdof(0);
  EXPECT_EQ(refusal(s), "frames must be in 1..1000000 (got 0)");
  s = sixdof(3);
  s.sixdof.distance_max = 1e300;  // finite, but the renderer's numbers would not be
  EXPECT_EQ(refusal(s).rfind("distance range must be 0 < A <= B metres", 0), 0u) << refusal(s);
}

TEST(SixdofRun, OurDetectorMatchesTheDistortedTruthAndTheRowsAreReproducible) {
  if (!test::have_povray()) GTEST_SKIP() << "povray is not installed";
  SweepSettings s = sixdof(6);
  s.sixdof.distance_max = 2;  // near enough that ours finds most frames
  s.detectors = {"tagbench", "libapriltag-d1"};
  const RenderOptions o = test::gentle_options(test::shared_cache());
  const SweepResult a = run_sweep(s, o), b = run_sweep(s, o);
  ASSERT_EQ(a.rows.size(), 12u);
  int found = 0;
  for (const SweepRow& row : a.rows) {
    if (row.detector != "tagbench" || !row.detected_right_id) continue;
    ++found;
    EXPECT_LT(row.corner_rms_px, 0.5);   // the truth is where the lens put the corners
    EXPECT_LT(row.orientation_error_deg, 5);  // and ours undistorts them for the pose
  }
  EXPECT_GE(found, 4);
  // Reproducible: every row and summary the same, timing aside.
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].detected_right_id, b.rows[i].detected_right_id);
    EXPECT_EQ(std::isnan(a.rows[i].corner_rms_px) ? -1 : a.rows[i].corner_rms_px,
              std::isnan(b.rows[i].corner_rms_px) ? -1 : b.rows[i].corner_rms_px);
  }
  // The summary: "all" and one bin of each variable per frame and detector.
  const auto summary = summarize(a);
  std::map<std::string, int> frames_per_variable;
  for (const SummaryRow& r : summary)
    if (r.detector == "tagbench") frames_per_variable[r.variable] += r.frames;
  EXPECT_EQ(frames_per_variable.size(), 9u);
  for (const auto& [v, n] : frames_per_variable) EXPECT_EQ(n, 6) << v;
  const std::string csv = rows_csv(a);
  EXPECT_EQ(csv.substr(0, csv.find('\n')).find("black_square_px,halton_index,k1,k2,p1,p2,k3,defocus_sigma_px,noise_sigma,"
                                                "quantization_bits,detector"),
            csv.substr(0, csv.find('\n')).find("black_square_px"));
  EXPECT_EQ(summary_csv(a, summary).rfind("experiment,variable,bin_lo,bin_hi,detector,frames,", 0), 0u);
}

}  // namespace test_sixdof
