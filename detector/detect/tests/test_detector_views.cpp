// The whole detector on tags warped into images by known homographies (supersampled): every shipped
// family, half resolution, bit errors, an occluded border, a lighting gradient, nothing in blank
// images, noise or texture, the pose of a synthetic view, and detect() shared by threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>
#include <thread>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"
#include "whole_detector.hpp"

namespace test_detector_views {

using namespace tagbench;
using tagbench::test_detector::opts;

namespace {

// A random perspective view of a tag: centre, size, in-plane angle, and a tilt (corner jitter).
Corners random_view(std::mt19937& rng, int w, int h, double side) {
  std::uniform_real_distribution<double> cx(side, w - side), cy(side, h - side), ang(-M_PI, M_PI), j(-0.12, 0.12);
  Corners c = synth::square_tag_corners(cx(rng), cy(rng), side, ang(rng));
  for (auto& p : c) p += side * Eigen::Vector2d(j(rng), j(rng));
  return c;
}

}  // namespace

TEST(Detector, EveryShippedFamilyRightIdRotationAndCorners) {
  std::mt19937 rng(21);
  const auto pending = pending_family_names();
  for (const auto& name : builtin_family_names()) {
    const TagFamily& f = builtin_family(name);
    if (!f.info().seed) continue;  // AprilTag families (the rival codebooks use other tag layouts)
    const Detector det(opts({name}, 0));
    for (const double side : {40.0, 70.0}) {
      const int id = static_cast<int>(rng() % f.size());
      const Corners truth = random_view(rng, 160, 150, side);
      const ImageF img = synth::render_tag(160, 150, tag_cells(f, id), synth::homography_for(truth), 0.5f, 6);
      const auto dets = det.detect(img);
      ASSERT_EQ(dets.size(), 1u) << name << " side " << side;
      EXPECT_EQ(dets[0].family, f.name());
      EXPECT_EQ(dets[0].id, id) << name;
      EXPECT_EQ(dets[0].hamming, 0);
      for (std::size_t i = 0; i < 4; ++i)
        EXPECT_LT((dets[0].corners[i] - truth[i]).norm(), 0.2) << name << " corner " << i << " side " << side;
      EXPECT_LT((dets[0].center - synth::homography_for(truth).col(2).hnormalized()).norm(), 0.2);
    }
  }
}

TEST(Detector, HalfResolutionFindsLargeTags) {
  const TagFamily& f = builtin_family("25h9");
  DetectorOptions o = opts({"25h9"});
  o.half_resolution = true;
  const Corners truth = synth::square_tag_corners(100, 90, 90, 0.5);
  const ImageF img = synth::render_tag(200, 180, tag_cells(f, 11), synth::homography_for(truth));
  const auto dets = Detector(o).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 11);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((dets[0].corners[i] - truth[i]).norm(), 1.0);
}

TEST(Detector, BitErrorsUpToMaxHammingDecodeBeyondNot) {
  const TagFamily& f = builtin_family("36h15");
  const Corners truth = synth::square_tag_corners(80, 80, 100, 0.3);
  const int id = 4;
  for (int errors = 0; errors <= 4; ++errors) {
    // Flip `errors` payload cells of the printed tag.
    TagCells cells = tag_cells(f, id);
    for (int e = 0; e < errors; ++e) {
      const int y = 2 + (e * 5) % 6, x = 2 + (e * 3 + 1) % 6;
      cells.white[static_cast<std::size_t>(y * cells.n + x)] ^= 1;
    }
    const ImageF img = synth::render_tag(160, 160, cells, synth::homography_for(truth));
    for (int k = 0; k <= 4; ++k) {
      const auto dets = Detector(opts({"36h15"}, k)).detect(img);
      if (errors <= k) {
        ASSERT_EQ(dets.size(), 1u) << errors << " errors, max " << k;
        EXPECT_EQ(dets[0].id, id);
        EXPECT_EQ(dets[0].hamming, errors);
      } else {
        EXPECT_TRUE(dets.empty()) << errors << " errors, max " << k;
      }
    }
  }
}

TEST(Detector, PartlyOccludedBorderEdgeStillDetected) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(90, 90, 100, 0.15);
  ImageF img = synth::render_tag(180, 180, tag_cells(f, 2), synth::homography_for(truth));
  // A grey blob covers the middle third of the bottom border edge (outside the payload).
  const Eigen::Vector2d a = truth[3], b = truth[2];
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Eigen::Vector2d p(x, y);
      const Eigen::Vector2d m = 0.5 * (a + b);
      if ((p - m).norm() < 16) img.at(x, y) = 0.5f;
    }
  const auto dets = Detector(opts({"25h9"}, 2)).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 2);
}

TEST(Detector, StrongLightingGradientStillDecoded) {
  const TagFamily& f = builtin_family("16h5");
  const Corners truth = synth::square_tag_corners(90, 80, 90, -0.4);
  ImageF img = synth::render_tag(180, 160, tag_cells(f, 9), synth::homography_for(truth));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) *= static_cast<float>(1.0 - 0.85 * x / img.width);
  const auto dets = Detector(opts({"16h5"}, 0)).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 9);
}

TEST(Detector, NothingInBlankNoiseOrTexture) {
  std::mt19937 rng(5);
  std::vector<ImageF> imgs;
  imgs.emplace_back(320, 240, 0.5f);
  ImageF noise(320, 240);
  std::uniform_real_distribution<float> u(0, 1);
  for (auto& v : noise.data) v = u(rng);
  imgs.push_back(noise);
  // Blocky texture: random rectangles, the kind of structure that makes quads.
  ImageF tex(320, 240, 0.5f);
  std::uniform_int_distribution<int> px(0, 300), sz(5, 60);
  for (int r = 0; r < 200; ++r) {
    const int x0 = px(rng), y0 = px(rng) % 220, w = sz(rng), h = sz(rng);
    const float v = u(rng);
    for (int y = y0; y < std::min(240, y0 + h); ++y)
      for (int x = x0; x < std::min(320, x0 + w); ++x) tex.at(x, y) = v;
  }
  imgs.push_back(tex);
  const Detector det(opts({"36h11"}, 0));
  for (const auto& img : imgs) EXPECT_TRUE(det.detect(img).empty());
}

TEST(Detector, PoseOfASyntheticView) {
  const TagFamily& f = builtin_family("36h15");
  DetectorOptions o = opts({"36h15"});
  o.camera = CameraIntrinsics{400, 400, 199.5, 199.5};
  o.tag_size = 0.2;
  // A tag 1.2 m away, tilted 35 degrees about a diagonal axis.
  Pose truth;
  truth.R = Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  truth.t = Eigen::Vector3d(0.05, -0.03, 1.2);
  const Corners c = project_tag_corners(truth, *o.camera, o.tag_size);
  const ImageF img = synth::render_tag(400, 400, tag_cells(f, 1), synth::homography_for(c));
  const auto dets = Detector(o).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  ASSERT_TRUE(dets[0].pose.has_value());
  EXPECT_LT(rotation_angle_deg(dets[0].pose->pose.R, truth.R), 0.5);
  EXPECT_LT(std::abs(dets[0].pose->pose.t.norm() - truth.t.norm()), 0.01 * truth.t.norm());
  ASSERT_TRUE(dets[0].pose_alternative.has_value());
  EXPECT_GT(rotation_angle_deg(dets[0].pose_alternative->pose.R, truth.R), 1.0);
  EXPECT_GE(dets[0].pose_alternative->reprojection_rms_px, dets[0].pose->reprojection_rms_px);
}

TEST(Detector, DetectIsConstAndThreadSafe) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(100, 100, 80, 0.7);
  const ImageF img = synth::render_tag(200, 200, tag_cells(f, 13), synth::homography_for(truth));
  const Detector det(opts({"25h9", "16h5"}));
  const auto reference = det.detect(img);
  ASSERT_EQ(reference.size(), 1u);
  std::vector<std::thread> pool;
  std::atomic<int> mismatches{0};
  for (int t = 0; t < 4; ++t)
    pool.emplace_back([&] {
      for (int i = 0; i < 5; ++i) {
        const auto d = det.detect(img);
        if (d.size() != 1 || d[0].id != 13 || (d[0].corners[0] - reference[0].corners[0]).norm() > 0) ++mismatches;
      }
    });
  for (auto& th : pool) th.join();
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace test_detector_views
