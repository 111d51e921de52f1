#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/photometric_refine.hpp"
#include "detect/pose.hpp"
#include "synthetic_tag.hpp"

namespace test_photometric_refine {

using namespace tagbench;

namespace {

using synth::corner_rms;
using synth::perturbed;

PhotometricRefineOptions on() { return PhotometricRefineOptions{}; }

}  // namespace

// Tags 24-60 px wide, rendered exactly (8x8 samples per pixel) and blurred as a lens would; corners
// off by up to 0.4 px come back to within 0.02 px.
TEST(PhotometricRefine, BlurredTagCornersComeBackToTheTruth) {
  const TagFamily& f = builtin_family("36h11");
  for (int k = 0; k < 5; ++k) {
    const double side = 24 + 9 * k;
    const Corners truth = synth::square_tag_corners(50.3 + 0.17 * k, 48.6 - 0.11 * k, side, 0.2 + 0.4 * k);
    ImageF img = synth::render_tag(100, 100, tag_cells(f, 7 + k), synth::homography_for(truth), 0.5f);
    img = gaussian_blur(img, 0.6 + 0.1 * k);
    const Corners start = perturbed(truth, 0.3, 20 + static_cast<std::uint32_t>(k));
    const auto r = refine_corners_photometric(img, tag_cells(f, 7 + k), start, on());
    ASSERT_TRUE(r.has_value()) << k;
    EXPECT_LT(corner_rms(*r, truth), 0.02) << k << " start " << corner_rms(start, truth);
  }
}

// A tag blurred and then gamma-encoded as a camera stores it: fitted on intensities linearised with
// the encoding's gamma the corners come back; fitted as they are, the lopsided steps shrink the square.
TEST(PhotometricRefine, GammaEncodedTagIsFittedOnLinearisedIntensities) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(50.3, 48.6, 40, 0.3);
  ImageF img = gaussian_blur(synth::render_tag(100, 100, tag_cells(f, 9), synth::homography_for(truth), 0.5f), 0.9);
  for (auto& v : img.data) v = std::pow(v, 1.0f / 2.2f);
  PhotometricRefineOptions lin = on();
  lin.gamma = 2.2;
  const auto a = refine_corners_photometric(img, tag_cells(f, 9), truth, on());
  const auto b = refine_corners_photometric(img, tag_cells(f, 9), truth, lin);
  ASSERT_TRUE(b.has_value());
  EXPECT_LT(corner_rms(*b, truth), 0.03);
  if (a) {
    EXPECT_GT(corner_rms(*a, truth), 2 * corner_rms(*b, truth));
  }
  lin.gamma = 0;  // no valid gamma: no refinement
  EXPECT_FALSE(refine_corners_photometric(img, tag_cells(f, 9), truth, lin).has_value());
}

// One workspace through tags of different sizes (its buffers left longer, and holding the last
// tag's numbers, when a smaller one follows), an occluded part left out, and a moved-from workspace:
// the very corners a fresh call gives.
TEST(PhotometricRefine, AReusedWorkspaceGivesTheSameCornersAsFreshBuffers) {
  const TagFamily& f = builtin_family("36h11");
  PhotometricWorkspace ws;
  for (int k = 0; k < 6; ++k) {
    const double side = k % 2 == 0 ? 150 - 20 * k : 20 + 6 * k;
    const Corners truth = synth::square_tag_corners(100.3, 99.6, side, 0.3 * k);
    ImageF img = synth::render_tag(200, 200, tag_cells(f, 3 + k), synth::homography_for(truth), 0.5f);
    img = gaussian_blur(img, 0.7);
    const Corners start = perturbed(truth, 0.3, 40 + static_cast<std::uint32_t>(k));
    const std::vector<TagBox> hidden = k == 3 ? std::vector<TagBox>{{0.5, 1.2, -1.2, 1.2}} : std::vector<TagBox>{};
    const auto fresh = refine_corners_photometric(img, tag_cells(f, 3 + k), start, on(), hidden);
    const auto reused = refine_corners_photometric(img, tag_cells(f, 3 + k), start, on(), hidden, &ws);
    ASSERT_TRUE(fresh.has_value()) << k;
    ASSERT_TRUE(reused.has_value()) << k;
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ((*fresh)[i], (*reused)[i]) << k << " corner " << i;
  }
  PhotometricWorkspace moved = std::move(ws);
  const Corners truth = synth::square_tag_corners(100.3, 99.6, 60, 0.4);
  const ImageF img = gaussian_blur(synth::render_tag(200, 200, tag_cells(f, 9), synth::homography_for(truth), 0.5f), 0.7);
  const auto a = refine_corners_photometric(img, tag_cells(f, 9), perturbed(truth, 0.3, 5), on(), {}, &ws);  // NOLINT(bugprone-use-after-move)
  const auto b = refine_corners_photometric(img, tag_cells(f, 9), perturbed(truth, 0.3, 5), on(), {}, &moved);
  ASSERT_TRUE(a.has_value() && b.has_value());
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ((*a)[i], (*b)[i]);
}

// A strongly slanted tag (about 60 degrees) with shading across it: the model's per-axis blur and
// affine contrast follow it.
TEST(PhotometricRefine, SlantedShadedTag) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = {Eigen::Vector2d(30.4, 40.2), Eigen::Vector2d(118.7, 52.9), Eigen::Vector2d(112.3, 81.6),
                         Eigen::Vector2d(36.9, 88.1)};
  ImageF img = synth::render_tag(150, 130, tag_cells(f, 11), synth::homography_for(truth), 0.4f);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) = static_cast<float>(img.at(x, y) * (0.7 + 0.003 * x));
  img = gaussian_blur(img, 0.8);
  const auto r = refine_corners_photometric(img, tag_cells(f, 11), perturbed(truth, 0.3, 3), on());
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(corner_rms(*r, truth), 0.02);
}

// Large tags (cells of 16-25 px: the selection skips whole blocks of pixels inside the cells) at
// several rotations (each row scanned over the tag's footprint only) and one in strong perspective:
// the corners still come back to the truth, the selection having kept every pixel near a transition.
TEST(PhotometricRefine, LargeRotatedTagsWithBlockSkipping) {
  const TagFamily& f = builtin_family("36h11");
  for (int k = 0; k < 4; ++k) {
    const double side = 130 + 20 * k;
    Corners truth = synth::square_tag_corners(160.3, 158.6, side, 0.15 + 0.35 * k);
    if (k == 3) truth[1] += Eigen::Vector2d(-25, 12), truth[2] += Eigen::Vector2d(-25, -12);  // perspective
    ImageF img = synth::render_tag(320, 320, tag_cells(f, 3 + k), synth::homography_for(truth), 0.5f);
    img = gaussian_blur(img, 0.9);
    const Corners start = perturbed(truth, 0.3, 40 + static_cast<std::uint32_t>(k));
    const auto r = refine_corners_photometric(img, tag_cells(f, 3 + k), start, on());
    ASSERT_TRUE(r.has_value()) << k;
    EXPECT_LT(corner_rms(*r, truth), 0.02) << k << " start " << corner_rms(start, truth);
  }
}

// A rendered tag at a known pose: the pose from the refined corners is within 0.1 degree of the truth
// (8-bit quantisation and sensor-like noise included).
TEST(PhotometricRefine, PoseFromRefinedCornersIsWithinATenthOfADegree) {
  const TagFamily& f = builtin_family("36h11");
  const CameraIntrinsics K{600, 600, 79.5, 59.5};
  const double s = 0.16;
  Pose truth;
  truth.R = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())).toRotationMatrix();
  truth.t = Eigen::Vector3d(0.01, -0.02, 1.3);
  const Corners c = project_tag_corners(truth, K, s);
  ImageF img = synth::render_tag(160, 120, tag_cells(f, 4), synth::homography_for(c), 0.5f);
  img = gaussian_blur(img, 0.7);
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0, 0.01f);
  for (float& v : img.data) v = std::round(std::clamp(v + noise(rng), 0.0f, 1.0f) * 255) / 255;
  const auto r = refine_corners_photometric(img, tag_cells(f, 4), perturbed(c, 0.3, 4), on());
  ASSERT_TRUE(r.has_value());
  const auto sols = tag_pose_solutions(*r, K, s);
  ASSERT_FALSE(sols.empty());
  EXPECT_LT(rotation_angle_deg(sols[0].pose.R, truth.R), 0.1);
  EXPECT_LT(corner_rms(*r, c), 0.03);
}

// No tag in the image (flat): the contrast cannot be positive, so the refinement refuses.
TEST(PhotometricRefine, FlatImageIsRefused) {
  const TagFamily& f = builtin_family("36h11");
  const ImageF img(80, 80, 0.5f);
  EXPECT_FALSE(refine_corners_photometric(img, tag_cells(f, 0), synth::square_tag_corners(40, 40, 30, 0.1), on()));
}

// The wrong pattern (another id) pulls the corners nowhere useful: either refused or not better than
// a perturbation of the start would make it, and never a move past max_corner_shift_px.
TEST(PhotometricRefine, MovesAreBounded) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(40.2, 39.7, 30, 0.3);
  ImageF img = synth::render_tag(80, 80, tag_cells(f, 1), synth::homography_for(truth), 0.5f);
  PhotometricRefineOptions o = on();
  o.max_corner_shift_px = 0.5;
  const Corners start = perturbed(truth, 0.3, 8);
  if (const auto r = refine_corners_photometric(img, tag_cells(f, 2), start, o)) {
    for (std::size_t i = 0; i < 4; ++i) EXPECT_LE(((*r)[i] - start[i]).norm(), 0.5);
  }
}

}  // namespace test_photometric_refine
