#include <gtest/gtest.h>

#include <cmath>

#include "detect/blur.hpp"
#include "detect/occlusion_refit.hpp"
#include "synthetic_occluded.hpp"

namespace test_occlusion_refit {

using namespace tagbench;

namespace {
double max_error(const Corners& a, const Corners& b) {
  double e = 0;
  for (std::size_t i = 0; i < 4; ++i) e = std::max(e, (a[i] - b[i]).norm());
  return e;
}
const Corners kTruth = synth::square_tag_corners(100.3, 95.6, 64, 0.45);
}  // namespace

TEST(OcclusionRefit, UnoccludedTagIsLeftAlone) {
  const ImageF img = synth::occluded_tag(kTruth, 0.0, 200, 190);
  const auto r = refit_occluded_sides(img, kTruth, 8);
  ASSERT_TRUE(r.corners);
  EXPECT_EQ(r.sides_refitted, 0);
  EXPECT_EQ(max_error(*r.corners, kTruth), 0.0);
}

TEST(OcclusionRefit, SideFittedToTheOccluderIsRefittedFromItsVisibleParts) {
  for (double fraction : {0.2, 0.5, 0.8}) {
    const ImageF img = synth::occluded_tag(kTruth, fraction, 200, 190);
    // The bottom side (BR -> BL) pulled 1.5 px outward, as a fit to the occluder's outline would.
    Corners c = kTruth;
    const Eigen::Vector2d n = (kTruth[3] - kTruth[0]).normalized();
    c[2] += 1.5 * n, c[3] += 1.5 * n;
    const auto r = refit_occluded_sides(img, c, 8);
    ASSERT_TRUE(r.corners) << fraction;
    EXPECT_GE(r.sides_refitted, 1) << fraction;
    EXPECT_LT(max_error(*r.corners, kTruth), 0.5) << fraction;
  }
}

// Blurred and gamma-encoded as a camera stores it: the side re-fitted from its visible part is placed
// on linear intensities with the detector's input gamma, inside the truth without it.
TEST(OcclusionRefit, RefittedSideIsLocatedOnLinearIntensities) {
  ImageF img = gaussian_blur(synth::occluded_tag(kTruth, 0.5, 200, 190), 1.5);
  for (auto& v : img.data) v = std::pow(v, 1.0f / 2.2f);
  Corners c = kTruth;
  const Eigen::Vector2d n = (kTruth[3] - kTruth[0]).normalized();
  c[2] += 1.5 * n, c[3] += 1.5 * n;
  OcclusionRefitOptions lin;
  lin.gamma = 2.2;
  const auto a = refit_occluded_sides(img, c, 8), b = refit_occluded_sides(img, c, 8, lin);
  ASSERT_TRUE(a.corners && b.corners);
  ASSERT_GE(b.sides_refitted, 1);
  // The bottom side's offset from the truth along its outward normal: inward (negative) without gamma.
  const auto offset = [&](const Corners& r) { return 0.5 * ((r[2] - kTruth[2]).dot(n) + (r[3] - kTruth[3]).dot(n)); };
  EXPECT_LT(offset(*a.corners), -0.1);
  EXPECT_LT(std::abs(offset(*b.corners)), 0.5 * std::abs(offset(*a.corners)));
  lin.gamma = std::nan("");  // no locator: kept as it is, never withdrawn
  const auto e = refit_occluded_sides(img, c, 8, lin);
  ASSERT_TRUE(e.corners);
  EXPECT_EQ(*e.corners, c);
}

TEST(OcclusionRefit, WholeSideHiddenIsWithdrawn) {
  const ImageF img = synth::occluded_tag(kTruth, 1.3, 200, 190);
  EXPECT_FALSE(refit_occluded_sides(img, kTruth, 8).corners);
}

}  // namespace test_occlusion_refit
