#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/payload_decode.hpp"
#include "detect/pose_choice.hpp"
#include "synthetic_tag.hpp"

namespace test_pose_choice {

using namespace tagbench;

namespace {

// A 36h11 tag 1 m away seen at `phi_deg` from its normal (tilted about the image's y axis), its
// image, and the planar ambiguity's two solutions from its exact corners.
struct GrazingView {
  CameraIntrinsics K{400, 400, 199.5, 199.5};
  double size = 0.166;
  Pose truth;
  ImageF img;
  std::vector<PoseSolution> solutions;
};

GrazingView grazing(double phi_deg, int id) {
  GrazingView v;
  v.truth.R = Eigen::AngleAxisd(phi_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() *
              Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  v.truth.t = Eigen::Vector3d(0.02, -0.01, 1.0);
  const Corners c = project_tag_corners(v.truth, v.K, v.size);
  v.img = gaussian_blur(synth::render_tag(400, 400, tag_cells(builtin_family("36h11"), id), synth::homography_for(c)), 0.5);
  v.solutions = tag_pose_solutions(c, v.K, v.size);
  return v;
}

}  // namespace

// The true pose's projection of the pattern correlates with the image better than the flipped one's.
TEST(PoseChoice, TruePatternCorrelatesBest) {
  const GrazingView v = grazing(75, 5);
  ASSERT_EQ(v.solutions.size(), 2u);
  const TagCells cells = tag_cells(builtin_family("36h11"), 5);
  const double truth = pattern_correlation(v.img, cells, project_tag_corners(v.truth, v.K, v.size), 3);
  EXPECT_GT(truth, 0.8);
  const double flipped = pattern_correlation(v.img, cells, project_tag_corners(v.solutions[1].pose, v.K, v.size), 3);
  EXPECT_GT(truth, flipped + 0.05);
}

// A detection reporting the flipped solution (as corners a few pixels off at a grazing view make the
// corners' reprojection error prefer it) gets the true one back; the true one stays; off: untouched.
TEST(PoseChoice, FlippedPoseIsSwappedForTheOneThePatternConfirms) {
  const GrazingView v = grazing(75, 5);
  ASSERT_EQ(v.solutions.size(), 2u);
  ASSERT_LT(rotation_angle_deg(v.solutions[0].pose.R, v.truth.R), 0.1);
  ASSERT_GT(rotation_angle_deg(v.solutions[1].pose.R, v.truth.R), 20);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  Detection d;
  d.family = "36h11";
  d.id = 5;
  d.pose = v.solutions[1];
  d.pose_alternative = v.solutions[0];
  d.pose_alternative->reprojection_rms_px = 2;  // as if the corners were off
  std::vector<Detection> flipped{d}, off{d};
  choose_poses_photometric(flipped, v.img, fams, v.K, v.size, PoseChoiceOptions{});
  EXPECT_LT(rotation_angle_deg(flipped[0].pose->pose.R, v.truth.R), 0.1);
  PoseChoiceOptions disabled;
  disabled.enabled = false;
  choose_poses_photometric(off, v.img, fams, v.K, v.size, disabled);
  EXPECT_GT(rotation_angle_deg(off[0].pose->pose.R, v.truth.R), 20);
  // A view gentler than min_view_angle_deg is left to the corners (a tag that is not one plane fools
  // the pattern there).
  PoseChoiceOptions steep;
  steep.min_view_angle_deg = 80;
  std::vector<Detection> gentle{d};
  choose_poses_photometric(gentle, v.img, fams, v.K, v.size, steep);
  EXPECT_GT(rotation_angle_deg(gentle[0].pose->pose.R, v.truth.R), 20);
  // The right pose reported: kept.
  std::swap(d.pose, d.pose_alternative);
  std::vector<Detection> right{d};
  choose_poses_photometric(right, v.img, fams, v.K, v.size, PoseChoiceOptions{});
  EXPECT_LT(rotation_angle_deg(right[0].pose->pose.R, v.truth.R), 0.1);
  // An alternative fitting the corners far worse than max_alternative_rms_px is no ambiguity.
  std::swap(d.pose, d.pose_alternative);
  d.pose_alternative->reprojection_rms_px = 20;
  std::vector<Detection> far{d};
  choose_poses_photometric(far, v.img, fams, v.K, v.size, PoseChoiceOptions{});
  EXPECT_GT(rotation_angle_deg(far[0].pose->pose.R, v.truth.R), 20);
}

namespace {

const std::array<double, 5> kLens{-0.2, 0.05, 0.001, -0.0005, 0};  // the sixdof sweep's lens

// The pinhole image `pinhole` as the lens `dist` shows it: each output (distorted) pixel takes the
// pinhole image's value where its undistorted point falls.
ImageF distort_image(const ImageF& pinhole, const CameraIntrinsics& K, const std::array<double, 5>& dist) {
  std::vector<cv::Point2d> in, out;
  for (int y = 0; y < pinhole.height; ++y)
    for (int x = 0; x < pinhole.width; ++x) in.emplace_back(x, y);
  const cv::Matx33d Km(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  cv::undistortPoints(in, out, Km, cv::Matx<double, 1, 5>(dist.data()), cv::noArray(), Km);
  ImageF img(pinhole.width, pinhole.height);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int x = static_cast<int>(i) % pinhole.width, y = static_cast<int>(i) / pinhole.width;
    img.at(x, y) = sample_bilinear(pinhole, Eigen::Vector2d(out[i].x, out[i].y)).value_or(0.5f);
  }
  return img;
}

}  // namespace

// project_tag_point is OpenCV's projectPoints (the lens model estimate_poses undistorts with).
TEST(PoseChoice, TagPointsProjectThroughTheLensAsOpenCV) {
  const CameraIntrinsics K{400, 410, 199.5, 189.5};
  Pose p;
  p.R = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1, 0.2).normalized())).toRotationMatrix();
  p.t = Eigen::Vector3d(0.3, -0.25, 0.9);
  const double size = 0.166;
  std::vector<cv::Point3d> X;
  const std::vector<std::pair<double, double>> u{{-1, -1}, {1, -1}, {0.3, 0.7}, {-0.6, 0.9}};
  for (auto [u1, u2] : u) X.emplace_back(u1 * size / 2, u2 * size / 2, 0);
  cv::Mat rvec, tvec = (cv::Mat_<double>(3, 1) << p.t.x(), p.t.y(), p.t.z());
  cv::Mat Rm(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Rm.at<double>(r, c) = p.R(r, c);
  cv::Rodrigues(Rm, rvec);
  std::vector<cv::Point2d> cvp;
  cv::projectPoints(X, rvec, tvec, cv::Matx33d(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1),
                    cv::Matx<double, 1, 5>(kLens.data()), cvp);
  for (std::size_t i = 0; i < u.size(); ++i) {
    const Eigen::Vector2d q = project_tag_point(p, K, size, kLens, u[i].first, u[i].second);
    EXPECT_NEAR(q.x(), cvp[i].x, 1e-9);
    EXPECT_NEAR(q.y(), cvp[i].y, 1e-9);
    // Without a lens: the pinhole corners of project_tag_corners.
    const Eigen::Vector2d pin = project_tag_point(p, K, size, std::nullopt, u[i].first, u[i].second);
    if (i == 0) {
      EXPECT_LT((pin - project_tag_corners(p, K, size)[0]).norm(), 1e-9);
    }
    EXPECT_GT((pin - q).norm(), 0.5);  // the lens moves points this far off-centre
  }
  Pose behind = p;
  behind.t.z() = -1;
  EXPECT_FALSE(project_tag_point(behind, K, size, kLens, 0, 0).allFinite());
}

// Without a lens, the pattern through the pose is the pattern through the corners' homography.
TEST(PoseChoice, CorrelationThroughThePoseEqualsTheCornersWithoutALens) {
  const GrazingView v = grazing(60, 7);
  const TagCells cells = tag_cells(builtin_family("36h11"), 7);
  const double by_corners = pattern_correlation(v.img, cells, project_tag_corners(v.truth, v.K, v.size), 3);
  const double by_pose = pattern_correlation_through_lens(v.img, cells, v.truth, v.K, v.size, std::nullopt, 3);
  EXPECT_NEAR(by_pose, by_corners, 1e-6);
  EXPECT_GT(by_pose, 0.8);
}

// Through a lens: the true pose's pattern, projected through the lens, fits the distorted image (the
// pinhole projection does not), and a flipped pose is swapped back only when with_lens.
TEST(PoseChoice, UnderALensThePatternGoesThroughTheLens) {
  GrazingView v = grazing(75, 5);
  ASSERT_EQ(v.solutions.size(), 2u);
  v.truth.t = Eigen::Vector3d(0.35, 0.3, 1.0);  // off-centre, where the lens bends the tag
  const Corners c = project_tag_corners(v.truth, v.K, v.size);
  const ImageF pin = gaussian_blur(synth::render_tag(400, 400, tag_cells(builtin_family("36h11"), 5), synth::homography_for(c)), 0.5);
  const ImageF img = distort_image(pin, v.K, kLens);
  const TagCells cells = tag_cells(builtin_family("36h11"), 5);
  const double lens = pattern_correlation_through_lens(img, cells, v.truth, v.K, v.size, kLens, 3);
  const double pinhole = pattern_correlation_through_lens(img, cells, v.truth, v.K, v.size, std::nullopt, 3);
  EXPECT_GT(lens, 0.8);
  EXPECT_GT(lens, pinhole + 0.1);

  const auto sols = tag_pose_solutions(c, v.K, v.size);  // the undistorted corners' two solutions
  ASSERT_EQ(sols.size(), 2u);
  ASSERT_LT(rotation_angle_deg(sols[0].pose.R, v.truth.R), 0.1);
  ASSERT_GT(rotation_angle_deg(sols[1].pose.R, v.truth.R), 20);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  Detection d;
  d.family = "36h11";
  d.id = 5;
  d.pose = sols[1];
  d.pose_alternative = sols[0];
  d.pose_alternative->reprojection_rms_px = 2;
  std::vector<Detection> on{d}, off{d};
  PoseChoiceOptions judge_all;
  judge_all.min_view_angle_deg = 0;  // the off-centre tag is seen less steeply than 75 degrees
  choose_poses_photometric(on, img, fams, v.K, v.size, judge_all, kLens);
  EXPECT_LT(rotation_angle_deg(on[0].pose->pose.R, v.truth.R), 0.1);
  EXPECT_GT(on[0].pose->pattern_correlation, on[0].pose_alternative->pattern_correlation);
  PoseChoiceOptions no_lens = judge_all;
  no_lens.with_lens = false;
  choose_poses_photometric(off, img, fams, v.K, v.size, no_lens, kLens);
  EXPECT_GT(rotation_angle_deg(off[0].pose->pose.R, v.truth.R), 20);
  EXPECT_TRUE(std::isnan(off[0].pose->pattern_correlation));
}

// Both solutions fitting the pattern within ambiguous_correlation_gap: marked, both correlations
// reported, the reported pose left as the corners chose it (below min_view_angle_deg: no swap).
TEST(PoseChoice, IndistinguishableSolutionsAreMarkedAmbiguous) {
  const GrazingView v = grazing(75, 5);
  ASSERT_EQ(v.solutions.size(), 2u);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  Detection d;
  d.family = "36h11";
  d.id = 5;
  d.pose = v.solutions[0];
  d.pose_alternative = v.solutions[1];
  d.pose_alternative->reprojection_rms_px = 1;
  PoseChoiceOptions opt;
  opt.min_view_angle_deg = 90;  // the gentle rule
  opt.gentle_max_alternative_rms_px = 2;
  opt.ambiguous_correlation_gap = 0.02;
  std::vector<Detection> clear{d};
  choose_poses_photometric(clear, v.img, fams, v.K, v.size, opt);
  EXPECT_FALSE(clear[0].pose_ambiguous);  // at 75 degrees the pattern tells them apart
  EXPECT_GT(clear[0].pose->pattern_correlation, clear[0].pose_alternative->pattern_correlation + 0.05);
  opt.ambiguous_correlation_gap = 2;  // any two correlations are within 2
  std::vector<Detection> within{d};
  choose_poses_photometric(within, v.img, fams, v.K, v.size, opt);
  EXPECT_TRUE(within[0].pose_ambiguous);
  EXPECT_LT(rotation_angle_deg(within[0].pose->pose.R, v.truth.R), 0.1);
  opt.ambiguous_correlation_gap = 0;  // never marked
  std::vector<Detection> unmarked{d};
  choose_poses_photometric(unmarked, v.img, fams, v.K, v.size, opt);
  EXPECT_FALSE(unmarked[0].pose_ambiguous);
  EXPECT_TRUE(std::isfinite(unmarked[0].pose->pattern_correlation));
  opt.gentle_max_alternative_rms_px = 0;  // gentle views not judged at all
  std::vector<Detection> off{d};
  choose_poses_photometric(off, v.img, fams, v.K, v.size, opt);
  EXPECT_FALSE(off[0].pose_ambiguous);
  EXPECT_TRUE(std::isnan(off[0].pose->pattern_correlation));
}

// A one-pixel-wide image: the shared bilinear sampler reads column 0 only (the inline copy it replaced
// indexed column -1 there: x0 = min(int(x), width - 2)). fx = 0 maps every point onto x = cx = 0.
TEST(PoseChoice, OnePixelWideImageIsSampledInside) {
  ImageF img(1, 50, 0.5f);
  for (int y = 0; y < 50; ++y) img.at(0, y) = y < 25 ? 0.f : 1.f;
  Pose p;
  p.t = Eigen::Vector3d(0, 0, 1);
  const CameraIntrinsics K{0, 200, 0, 24.5};  // the 0.166 m tag spans y 8..41
  const double r = pattern_correlation_through_lens(img, tag_cells(builtin_family("36h11"), 0), p, K, 0.166, std::nullopt, 3);
  ASSERT_TRUE(std::isfinite(r));
  EXPECT_LE(std::abs(r), 1.0);
}

// The gentle rule: below min_view_angle_deg a flipped pose is swapped back when the alternative fits
// the corners within gentle_max_alternative_rms_px, and left when it fits them worse.
TEST(PoseChoice, GentleViewsAreJudgedWhenBothSolutionsFitTheCorners) {
  const GrazingView v = grazing(35, 9);
  ASSERT_EQ(v.solutions.size(), 2u);
  ASSERT_GT(rotation_angle_deg(v.solutions[1].pose.R, v.truth.R), 20);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  Detection d;
  d.family = "36h11";
  d.id = 9;
  d.pose = v.solutions[1];
  d.pose_alternative = v.solutions[0];
  d.pose->reprojection_rms_px = 0.1;
  d.pose_alternative->reprojection_rms_px = 0.3;  // both within the corners' noise
  PoseChoiceOptions opt;
  ASSERT_LT(35, opt.min_view_angle_deg);
  std::vector<Detection> fits{d};
  choose_poses_photometric(fits, v.img, fams, v.K, v.size, opt);
  EXPECT_LT(rotation_angle_deg(fits[0].pose->pose.R, v.truth.R), 0.1);
  EXPECT_GT(fits[0].pose->pattern_correlation, fits[0].pose_alternative->pattern_correlation);
  d.pose_alternative->reprojection_rms_px = opt.gentle_max_alternative_rms_px + 0.5;
  std::vector<Detection> worse{d};
  choose_poses_photometric(worse, v.img, fams, v.K, v.size, opt);
  EXPECT_GT(rotation_angle_deg(worse[0].pose->pose.R, v.truth.R), 20);
  EXPECT_TRUE(std::isnan(worse[0].pose->pattern_correlation));
}

// A blurred pattern model fits a defocused image better than the sharp pattern (the gentle rule's
// gentle_model_blur_px), and best near the image's own blur.
TEST(PoseChoice, BlurredPatternFitsADefocusedImageBetter) {
  GrazingView v = grazing(20, 3);
  const Corners c = project_tag_corners(v.truth, v.K, v.size);
  const TagCells cells = tag_cells(builtin_family("36h11"), 3);
  const ImageF img = gaussian_blur(synth::render_tag(400, 400, cells, synth::homography_for(c)), 2.0);
  const double sharp = pattern_correlation_through_lens(img, cells, v.truth, v.K, v.size, std::nullopt, 5, 0);
  const double matched = pattern_correlation_through_lens(img, cells, v.truth, v.K, v.size, std::nullopt, 5, 2.0);
  const double over = pattern_correlation_through_lens(img, cells, v.truth, v.K, v.size, std::nullopt, 5, 8.0);
  EXPECT_GT(matched, sharp + 0.01);
  EXPECT_GT(matched, over);
  EXPECT_GT(matched, 0.97);
}

}  // namespace test_pose_choice
