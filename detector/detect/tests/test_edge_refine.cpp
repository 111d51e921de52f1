#include <gtest/gtest.h>

#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/edge_refine.hpp"
#include "detect/payload_decode.hpp"
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

// The scan's vectorised sampling gives sample_bilinear_inside's values bit for bit: random images,
// points and directions, odd and even step counts, points on the last row and column (the clamps).
TEST(EdgeRefine, ScanSamplesEqualScalarBilinearBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    ImageF img;
    img.width = 2 + static_cast<int>(u01(rng) * 30), img.height = 2 + static_cast<int>(u01(rng) * 30);
    img.data.resize(static_cast<std::size_t>(img.width * img.height));
    for (float& v : img.data) v = static_cast<float>(u01(rng));
    const double a = u01(rng) * 2 * M_PI;
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    const double range = 0.5 + 2 * u01(rng);
    const int count = 1 + static_cast<int>(u01(rng) * 25);
    std::vector<EdgeRefineScratch::Step> steps;
    for (int j = 0; j < count; ++j) steps.push_back({0, -range + 2 * range * j / std::max(1, count - 1), 0, -1});
    // A centre whose whole scan is inside, sometimes pushed onto the last column / row.
    const double m = range + 1e-9;
    if (img.width - 1 < 2 * m || img.height - 1 < 2 * m) continue;
    Eigen::Vector2d p(m + u01(rng) * (img.width - 1 - 2 * m), m + u01(rng) * (img.height - 1 - 2 * m));
    if (trial % 5 == 0) {  // a scan along the image's last column, ending on its corner
      p = Eigen::Vector2d(img.width - 1.0, img.height - 1.0 - range);
      steps.clear();
      for (int j = 0; j < count; ++j) steps.push_back({0, range * j / std::max(1, count - 1), 0, -1});
      const Eigen::Vector2d down(0, 1);
      std::vector<float> got(steps.size());
      detail::sample_scan(img, p, down, steps, got.data());
      for (std::size_t j = 0; j < steps.size(); ++j)
        EXPECT_EQ(got[j], sample_bilinear_inside(img, p + steps[j].hi * down)) << trial << " " << j;
      continue;
    }
    std::vector<float> got(steps.size());
    detail::sample_scan(img, p, n, steps, got.data());
    for (std::size_t j = 0; j < steps.size(); ++j)
      EXPECT_EQ(got[j], sample_bilinear_inside(img, p + steps[j].hi * n)) << trial << " " << j;
  }
}

}  // namespace test_edge_refine
