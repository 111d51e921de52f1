// POV-Ray frames and their ground truth (issue 4, section 1): the render camera, the view poses and
// the projected corners, and the scene conventions proved by our detector finding the rendered corners
// where the ground truth puts them, in the plain and the realistic scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "raytrace/render.hpp"
#include "test_frames.hpp"

namespace test_render_geometry {

using namespace tagbench;
using namespace tagbench::bench;
using tagbench::bench::test::gentle_options;
using tagbench::bench::test::max_corner_error;
using tagbench::bench::test::plain_frames;
using tagbench::bench::test::shared_cache;

namespace {

// Pixels of `gray` outside the whole printed tag (its projected outline grown by `margin` px).
cv::Mat outside_tag_mask(const FramePose& f, double margin) {
  FramePose whole = f;
  whole.tag_size = f.tag_size * 10 / 8;  // 36h11: the printed tag is 10 cells, the black square 8
  const Corners c = ground_truth(whole).corners;
  std::vector<cv::Point> poly;
  const Eigen::Vector2d centre = (c[0] + c[1] + c[2] + c[3]) / 4;
  for (const auto& p : c) {
    const Eigen::Vector2d q = p + (p - centre).normalized() * margin;
    poly.emplace_back(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())));
  }
  cv::Mat mask(kRenderHeight, kRenderWidth, CV_8UC1, cv::Scalar(255));
  cv::fillConvexPoly(mask, poly, cv::Scalar(0));
  return mask;
}

}  // namespace

TEST(RaytraceGeometry, RenderCameraIsThePapersPinhole) {
  const CameraIntrinsics K = render_camera();
  EXPECT_EQ(K.fx, 400);
  EXPECT_EQ(K.fy, 400);
  EXPECT_EQ(K.cx, 199.5);  // the optical axis passes between pixels 199 and 200
  EXPECT_EQ(K.cy, 199.5);
}

TEST(RaytraceGeometry, ViewPoseHasTheRequestedDistanceAngleAndImagePoint) {
  const CameraIntrinsics K = render_camera();
  for (const double phi : {0.0, 30.0, 85.0}) {
    for (const double axis : {0.0, 70.0, 200.0}) {
      const ViewSpec v{.distance = 2.5, .phi_deg = phi, .tilt_axis_deg = axis, .roll_deg = 40, .pixel = {120.0, 260.0}};
      const Pose p = view_pose(v);
      EXPECT_NEAR((p.R.transpose() * p.R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
      EXPECT_NEAR(p.R.determinant(), 1, 1e-12);
      EXPECT_NEAR(p.t.norm(), 2.5, 1e-12);
      EXPECT_NEAR(K.fx * p.t.x() / p.t.z() + K.cx, 120, 1e-9);
      EXPECT_NEAR(K.fy * p.t.y() / p.t.z() + K.cy, 260, 1e-9);
      // The printed face's normal (-z of the tag) against the direction to the camera (-t).
      const Eigen::Vector3d normal = -p.R.col(2), to_camera = -p.t.normalized();
      EXPECT_NEAR(std::acos(std::clamp(normal.dot(to_camera), -1.0, 1.0)) * 180 / M_PI, phi, 1e-6);
    }
  }
  // Face-on at the image centre, roll 0: the tag's axes are the camera's; a roll turns the printed
  // top-left corner clockwise in the image (toward the top edge, then the right).
  const Pose p0 = view_pose({.distance = 1});
  EXPECT_NEAR((p0.R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  FramePose f;
  f.tag_size = 0.2;
  f.pose = view_pose({.distance = 1, .roll_deg = 90});
  const Corners c = ground_truth(f).corners;
  EXPECT_NEAR(c[0].x(), 199.5 + 40, 1e-9);  // TL now at the top-right
  EXPECT_NEAR(c[0].y(), 199.5 - 40, 1e-9);
  EXPECT_THROW(view_pose({.distance = 0}), std::invalid_argument);
  EXPECT_THROW(view_pose({.distance = 1, .phi_deg = 90}), std::invalid_argument);
}

TEST(RaytraceGeometry, GroundTruthCornersAreTheProjectedBlackSquareInPrintedOrder) {
  FramePose f;
  f.tag_size = 0.2;
  f.pose.t = Eigen::Vector3d(0, 0, 1);  // face-on, 1 m: the black square is 400 * 0.2 = 80 px wide
  const GroundTruth g = ground_truth(f);
  EXPECT_NEAR(g.black_square_px, 80, 1e-9);
  const double lo = 199.5 - 40, hi = 199.5 + 40;
  EXPECT_TRUE(g.corners[0].isApprox(Eigen::Vector2d(lo, lo)));  // top-left
  EXPECT_TRUE(g.corners[1].isApprox(Eigen::Vector2d(hi, lo)));  // top-right
  EXPECT_TRUE(g.corners[2].isApprox(Eigen::Vector2d(hi, hi)));  // bottom-right
  EXPECT_TRUE(g.corners[3].isApprox(Eigen::Vector2d(lo, hi)));  // bottom-left
}

// The scene conventions (camera, S R S matrix, image_map orientation, principal point): our detector
// finds the rendered black square where the ground truth projects it, in printed order.
TEST(RaytraceRender, OurDetectorFindsThePlainFramesAtTheGroundTruth) {
  REQUIRE_POVRAY();
  const auto frames = plain_frames();
  const RenderReport r = render_frames(frames, scene_template(SceneKind::kPlain), gentle_options(shared_cache()));
  ASSERT_EQ(r.failed, 0u);
  DetectorOptions opt = DetectorOptions::paper();
  opt.camera = render_camera();
  opt.tag_size = frames[0].tag_size;
  const Detector detector(opt);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    ASSERT_TRUE(r.frames[i].ok()) << r.frames[i].error;
    const cv::Mat img = read_frame_gray(r.frames[i].png);
    ASSERT_EQ(img.cols, 400);
    ASSERT_EQ(img.rows, 400);
    const auto dets = detect(detector, img);
    ASSERT_EQ(dets.size(), 1u) << "frame " << i;
    const Detection& d = dets[0];
    EXPECT_EQ(d.id, frames[i].id);
    const GroundTruth g = ground_truth(frames[i]);
    const double corner = max_corner_error(d.corners, g.corners);
    ASSERT_TRUE(d.pose.has_value());
    const double orient = rotation_angle_deg(d.pose->pose.R, g.pose.R);
    const double dist = 100 * std::abs(d.pose->pose.t.norm() - g.pose.t.norm()) / g.pose.t.norm();
    std::printf("frame %zu (id %d, %.0f px): corner max %.3f px, orientation %.3f deg, distance %.3f %%\n", i,
                frames[i].id, g.black_square_px, corner, orient, dist);
    EXPECT_LT(corner, 0.3) << "frame " << i;
    EXPECT_LT(orient, 1.0) << "frame " << i;
    EXPECT_LT(dist, 1.0) << "frame " << i;
    // Plain scene: everything away from the tag is the uniform grey background.
    double lo = 0, hi = 0;
    cv::minMaxLoc(img, &lo, &hi, nullptr, nullptr, outside_tag_mask(frames[i], 3));
    EXPECT_EQ(lo, hi) << "frame " << i;
    EXPECT_NEAR(lo, 128, 1);  // rgb 0.5, linear output
  }
}

TEST(RaytraceRender, RealisticSceneShowsMoreThanTheTagAndTheTagIsFound) {
  REQUIRE_POVRAY();
  FramePose f;
  f.id = 42;
  f.pose = view_pose({.distance = 1.2, .phi_deg = 35, .tilt_axis_deg = 80, .roll_deg = 15, .pixel = {190.0, 170.0}});
  const RenderReport r = render_frames({f}, scene_template(SceneKind::kRealistic), gentle_options(shared_cache()));
  ASSERT_TRUE(r.frames[0].ok()) << r.frames[0].error;
  const cv::Mat img = read_frame_gray(r.frames[0].png);
  // The floor and wall are textured: well away from the tag the picture is anything but uniform.
  const cv::Mat outside = outside_tag_mask(f, 10);
  double lo = 0, hi = 0;
  cv::minMaxLoc(img, &lo, &hi, nullptr, nullptr, outside);
  EXPECT_GT(hi - lo, 60) << "textures and light in view";
  DetectorOptions opt = DetectorOptions::paper();
  opt.camera = render_camera();
  opt.tag_size = f.tag_size;
  const auto dets = detect(Detector(opt), img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 42);
  const GroundTruth g = ground_truth(f);
  const double corner = max_corner_error(dets[0].corners, g.corners);
  std::printf("realistic: corner max %.3f px, orientation %.3f deg\n", corner,
              rotation_angle_deg(dets[0].pose->pose.R, g.pose.R));
  EXPECT_LT(corner, 0.5);
}

}  // namespace test_render_geometry
