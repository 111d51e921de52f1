#include <gtest/gtest.h>

#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/edge_refine.hpp"
#include "synthetic_tag.hpp"

namespace test_edge_refine {

using namespace tagbench;

namespace {

using synth::corner_rms;
using synth::perturbed;

}  // namespace

// A 20 px tag (2.5 px cells) rendered exactly, then blurred as a lens would: corners off by up to
// 0.8 px come back to within a tenth of a pixel, on many seeds and rotations.
TEST(EdgeRefine, SmallBlurredTagCornersComeBackToTheTruth) {
  const TagFamily& f = builtin_family("36h11");
  for (int k = 0; k < 6; ++k) {
    const Corners truth = synth::square_tag_corners(31.3 + 0.1 * k, 29.6, 20.0, 0.3 + 0.5 * k);
    ImageF img = synth::render_tag(64, 64, tag_cells(f, 3 + k), synth::homography_for(truth));
    img = gaussian_blur(img, 0.7);
    const Corners start = perturbed(truth, 0.8, 10 + static_cast<std::uint32_t>(k));
    const auto r = refine_quad_edges(img, start);
    ASSERT_TRUE(r.has_value()) << k;
    EXPECT_LT(corner_rms(*r, truth), 0.12) << k << " start " << corner_rms(start, truth);
    EXPECT_LT(corner_rms(*r, truth), corner_rms(start, truth)) << k;
  }
}

TEST(EdgeRefine, LargePerspectiveTagIsRefinedToo) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = {Eigen::Vector2d(40.3, 35.8), Eigen::Vector2d(130.1, 45.2), Eigen::Vector2d(125.4, 128.9),
                         Eigen::Vector2d(35.6, 120.2)};
  const ImageF img = synth::render_tag(170, 165, tag_cells(f, 4), synth::homography_for(truth));
  EdgeRefineOptions opt;
  opt.cells_across = 7;
  const auto r = refine_quad_edges(img, perturbed(truth, 1.0, 5), opt);
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(corner_rms(*r, truth), 0.1);
}

// No edge at all: every side keeps its line, so the corners are the input's.
TEST(EdgeRefine, FlatImageKeepsTheCorners) {
  const ImageF img(50, 50, 0.5f);
  const Corners c = synth::square_tag_corners(25, 25, 20, 0.1);
  const auto r = refine_quad_edges(img, c);
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(corner_rms(*r, c), 1e-9);
}

TEST(EdgeRefine, ALargeMoveIsRejected) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(32, 32, 24, 0.2);
  const ImageF img = synth::render_tag(64, 64, tag_cells(f, 1), synth::homography_for(truth));
  Corners start = truth;
  for (auto& p : start) p += Eigen::Vector2d(0.9, 0);  // the whole quad shifted right
  EdgeRefineOptions opt;
  opt.max_corner_shift_px = 0.3;
  EXPECT_FALSE(refine_quad_edges(img, start, opt).has_value());
  opt.max_corner_shift_px = 3;
  const auto r = refine_quad_edges(img, start, opt);
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(corner_rms(*r, truth), 0.1);
}

TEST(EdgeRefine, DegenerateQuadIsRejected) {
  const ImageF img(50, 50, 0.5f);
  const Corners c = {Eigen::Vector2d(10, 10), Eigen::Vector2d(10, 10), Eigen::Vector2d(20, 20), Eigen::Vector2d(10, 20)};
  EXPECT_FALSE(refine_quad_edges(img, c).has_value());
  EXPECT_FALSE(refine_quad_edges(ImageF(), synth::square_tag_corners(25, 25, 20, 0)).has_value());
}

// A camera's encoding gamma makes the blurred step lopsided: on the encoded image the steepest
// point moves toward the dark side, so gamma 1 shrinks the quad; gamma 2.2 undoes the encoding.
TEST(EdgeRefine, GammaEncodedEdgesAreLocatedOnLinearisedIntensities) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(40.2, 39.7, 40.0, 0.35);
  ImageF img = gaussian_blur(synth::render_tag(80, 80, tag_cells(f, 6), synth::homography_for(truth), 0.5f, 8, 0.02f, 0.9f), 1.2);
  for (auto& v : img.data) v = std::pow(v, 1.0f / 2.2f);
  const Corners start = perturbed(truth, 0.5, 3);
  EdgeRefineOptions lin;
  lin.gamma = 2.2;
  const auto a = refine_quad_edges(img, start), b = refine_quad_edges(img, start, lin);
  ASSERT_TRUE(a && b);
  EXPECT_LT(corner_rms(*b, truth), 0.08);
  EXPECT_GT(corner_rms(*a, truth), 2 * corner_rms(*b, truth));
}

}  // namespace test_edge_refine
