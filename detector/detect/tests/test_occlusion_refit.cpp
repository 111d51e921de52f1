#include <gtest/gtest.h>

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

TEST(OcclusionRefit, WholeSideHiddenIsWithdrawn) {
  const ImageF img = synth::occluded_tag(kTruth, 1.3, 200, 190);
  EXPECT_FALSE(refit_occluded_sides(img, kTruth, 8).corners);
}

}  // namespace test_occlusion_refit
