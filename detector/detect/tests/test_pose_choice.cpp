#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/pose_choice.hpp"
#include "synthetic_tag.hpp"

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
