// Stage 7: poses from detections' corners, refined or from the homography, with distortion.
#include <gtest/gtest.h>

#include <vector>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "detect/estimate_poses.hpp"

namespace test_estimate_poses {

using namespace tagbench;

namespace {

const CameraIntrinsics kK{420, 410, 200, 190};
constexpr double kSize = 0.15;

Pose truth_pose() {
  Pose p;
  p.R = Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 0.3, 0).normalized()).toRotationMatrix();
  p.t = Eigen::Vector3d(0.04, -0.02, 0.9);
  return p;
}

Detection with_corners(const Corners& c) {
  Detection d;
  d.id = 5;
  d.corners = c;
  return d;
}

}  // namespace

TEST(EstimatePoses, RefinedGivesBothSolutionsHomographyOne) {
  const Corners c = project_tag_corners(truth_pose(), kK, kSize);
  std::vector<Detection> dets = {with_corners(c)};
  estimate_poses(dets, kK, kSize, std::nullopt, true);
  ASSERT_TRUE(dets[0].pose);
  EXPECT_LT(rotation_angle_deg(dets[0].pose->pose.R, truth_pose().R), 1e-3);
  EXPECT_LT((dets[0].pose->pose.t - truth_pose().t).norm(), 1e-6);
  ASSERT_TRUE(dets[0].pose_alternative);
  EXPECT_GE(dets[0].pose_alternative->reprojection_rms_px, dets[0].pose->reprojection_rms_px);
  EXPECT_EQ(dets[0].corners, c);  // the observed corners stay
  EXPECT_EQ(dets[0].id, 5);

  dets = {with_corners(c)};
  estimate_poses(dets, kK, kSize, std::nullopt, false);
  ASSERT_TRUE(dets[0].pose);
  EXPECT_FALSE(dets[0].pose_alternative);
  EXPECT_LT(rotation_angle_deg(dets[0].pose->pose.R, truth_pose().R), 1e-3);
  EXPECT_LT(dets[0].pose->reprojection_rms_px, 1e-6);
}

TEST(EstimatePoses, UndistortsTheCornersFirst) {
  const std::array<double, 5> k = {-0.3, 0.1, 0.002, -0.003, 0.0};
  const double size = 0.6;  // a big tag, so that its corners are far from the image centre
  const Corners ideal = project_tag_corners(truth_pose(), kK, size);
  // Distort the ideal corners with OpenCV's model (through normalised coordinates).
  const cv::Matx33d Km(kK.fx, 0, kK.cx, 0, kK.fy, kK.cy, 0, 0, 1);
  std::vector<cv::Point3d> norm;
  for (const auto& p : ideal) norm.emplace_back((p.x() - kK.cx) / kK.fx, (p.y() - kK.cy) / kK.fy, 1.0);
  std::vector<cv::Point2d> out;
  cv::projectPoints(norm, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), Km, std::vector<double>(k.begin(), k.end()), out);
  Corners distorted;
  for (std::size_t i = 0; i < 4; ++i) distorted[i] = Eigen::Vector2d(out[i].x, out[i].y);
  ASSERT_GT((distorted[0] - ideal[0]).norm(), 3.0);  // the distortion moves corners by pixels

  std::vector<Detection> dets = {with_corners(distorted)};
  estimate_poses(dets, kK, size, k, true);
  ASSERT_TRUE(dets[0].pose);
  EXPECT_LT(rotation_angle_deg(dets[0].pose->pose.R, truth_pose().R), 0.05);
  EXPECT_LT((dets[0].pose->pose.t - truth_pose().t).norm(), 1e-4);
  EXPECT_EQ(dets[0].corners, distorted);

  std::vector<Detection> ignored = {with_corners(distorted)};
  estimate_poses(ignored, kK, size, std::nullopt, true);
  ASSERT_TRUE(ignored[0].pose);
  EXPECT_GT((ignored[0].pose->pose.t - truth_pose().t).norm(), 10 * (dets[0].pose->pose.t - truth_pose().t).norm());
}

}  // namespace test_estimate_poses
