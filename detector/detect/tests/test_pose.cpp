#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "detect/pose.hpp"

namespace test_pose {

using namespace tagbench;

namespace {

const CameraIntrinsics kCam{400, 400, 199.5, 199.5};  // the paper's 400x400, f = 400 px camera

Pose make_pose(double roll_deg, double pitch_deg, double yaw_deg, Eigen::Vector3d t) {
  const double d = M_PI / 180;
  Pose p;
  p.R = (Eigen::AngleAxisd(yaw_deg * d, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch_deg * d, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_deg * d, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  p.t = t;
  return p;
}

}  // namespace

TEST(Pose, FromHomographyRecoversASyntheticView) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ang(-50, 50), xy(-0.3, 0.3), z(1.0, 4.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose truth = make_pose(ang(rng), ang(rng), ang(rng) * 3, Eigen::Vector3d(xy(rng), xy(rng), z(rng)));
    const double size = 0.166;
    const Corners c = project_tag_corners(truth, kCam, size);
    const auto H = tag_homography(c);
    ASSERT_TRUE(H.has_value());
    const Pose est = pose_from_homography(*H, kCam, size);
    EXPECT_LT(rotation_angle_deg(est.R, truth.R), 0.5);
    EXPECT_LT(std::abs(est.t.norm() - truth.t.norm()), 0.01 * truth.t.norm());
    EXPECT_GT(est.t.z(), 0);
    EXPECT_NEAR(est.R.determinant(), 1.0, 1e-9);
  }
}

TEST(Pose, TagAxesFollowTheConvention) {
  // Face-on, upright, 1 m ahead: tag x = camera x (right), tag y = camera y (down), z into the tag = forward.
  const Pose truth = make_pose(0, 0, 0, Eigen::Vector3d(0, 0, 1));
  const Corners c = project_tag_corners(truth, kCam, 0.2);
  EXPECT_LT(c[0].x(), c[1].x());  // top-left left of top-right
  EXPECT_LT(c[1].y(), c[2].y());  // top-right above bottom-right
  EXPECT_NEAR(c[0].x(), 199.5 - 40, 1e-9);
  const Pose est = pose_from_homography(*tag_homography(c), kCam, 0.2);
  EXPECT_LT((est.R - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_LT((est.t - Eigen::Vector3d(0, 0, 1)).norm(), 1e-9);
}

TEST(Pose, RefinementReducesReprojectionErrorOnNoisyCorners) {
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0, 0.3);
  const Pose truth = make_pose(20, -35, 10, Eigen::Vector3d(0.1, -0.05, 2.0));
  Corners c = project_tag_corners(truth, kCam, 0.3);
  for (auto& p : c) p += Eigen::Vector2d(noise(rng), noise(rng));
  const Pose init = pose_from_homography(*tag_homography(c), kCam, 0.3);
  const Pose ref = refine_pose(init, c, kCam, 0.3);
  EXPECT_LE(corner_rms_error(ref, c, kCam, 0.3), corner_rms_error(init, c, kCam, 0.3) + 1e-12);
  EXPECT_LT(corner_rms_error(ref, c, kCam, 0.3), 0.5);
}

TEST(Pose, BothSolutionsOfTheAmbiguityAreReturned) {
  // A small, nearly face-on tag: the classic flip. The truth must be one of the two solutions, and the
  // other must differ in orientation while explaining the corners almost as well.
  const Pose truth = make_pose(12, 8, 30, Eigen::Vector3d(0.2, 0.1, 3.0));
  const Corners c = project_tag_corners(truth, kCam, 0.166);
  const auto sols = tag_pose_solutions(c, kCam, 0.166);
  ASSERT_EQ(sols.size(), 2u);
  EXPECT_LE(sols[0].reprojection_rms_px, sols[1].reprojection_rms_px);
  EXPECT_LT(rotation_angle_deg(sols[0].pose.R, truth.R), 0.01);
  EXPECT_LT(std::abs(sols[0].pose.t.norm() - truth.t.norm()), 1e-4 * truth.t.norm());
  EXPECT_GT(rotation_angle_deg(sols[1].pose.R, truth.R), 5.0);
  EXPECT_LT(sols[1].reprojection_rms_px, 0.5);  // nearly as good: that is why flips happen
  EXPECT_GT(sols[1].pose.t.z(), 0);
}

TEST(Pose, RotationAngle) {
  const Pose a = make_pose(0, 0, 0, Eigen::Vector3d::Zero()), b = make_pose(0, 0, 37, Eigen::Vector3d::Zero());
  EXPECT_NEAR(rotation_angle_deg(a.R, b.R), 37, 1e-9);
  EXPECT_TRUE(kCam.valid());
  EXPECT_FALSE((CameraIntrinsics{-1, 400, 0, 0}.valid()));
  EXPECT_FALSE((CameraIntrinsics{std::nan(""), 400, 0, 0}.valid()));
}

}  // namespace test_pose
