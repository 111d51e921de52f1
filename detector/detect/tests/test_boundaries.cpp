#include <gtest/gtest.h>

#include "detect/boundaries.hpp"
#include "detect/threshold.hpp"

using namespace tagbench;

namespace {
// A dark w x w square at (x0, y0) on light ground, as a ternary image.
TernaryImage square(int W, int H, int x0, int y0, int w) {
  TernaryImage t{W, H, std::vector<std::uint8_t>(static_cast<std::size_t>(W * H), kTernaryLight)};
  for (int y = y0; y < y0 + w; ++y)
    for (int x = x0; x < x0 + w; ++x) t.data[static_cast<std::size_t>(y * W + x)] = kTernaryDark;
  return t;
}
}  // namespace

TEST(Boundaries, OneSquareGivesOneGroupOnItsOutlineWithGradientsOutward) {
  const auto t = square(30, 30, 10, 8, 9);
  const auto c = connected_components(t);
  const auto g = group_boundaries(t, c);
  ASSERT_EQ(g.count(), 1u);
  const auto pts = g.group(0);
  EXPECT_GT(pts.size(), 4u * 9u);
  const double cx = 10 + 4, cy = 8 + 4;
  for (const auto& p : pts) {
    const double x = p.x2 / 2.0, y = p.y2 / 2.0;
    // On the square's outline: half a pixel outside the dark pixels' centres on some side.
    const bool on = (std::abs(x - cx) <= 5 && std::abs(y - cy) <= 5) && (std::abs(x - cx) >= 4 || std::abs(y - cy) >= 4);
    EXPECT_TRUE(on) << x << "," << y;
    EXPECT_GT((x - cx) * p.gx + (y - cy) * p.gy, 0) << x << "," << y;  // toward the light outside
  }
}

TEST(Boundaries, SmallComponentsAreIgnoredAndSeparateSquaresGiveSeparateGroups) {
  auto t = square(40, 20, 2, 2, 8);
  for (int y = 3; y < 11; ++y)
    for (int x = 20; x < 28; ++x) t.data[static_cast<std::size_t>(y * 40 + x)] = kTernaryDark;
  t.data[static_cast<std::size_t>(15 * 40 + 35)] = kTernaryDark;  // a 1-pixel speck
  const auto c = connected_components(t);
  const auto g = group_boundaries(t, c);
  EXPECT_EQ(g.count(), 2u);  // the speck (1 px < 25) makes none
  BoundaryOptions none;
  none.min_component_pixels = 1;
  EXPECT_EQ(group_boundaries(t, c, none).count(), 3u);
  // Groups in raster order of their first point; together every point once.
  EXPECT_EQ(g.offsets.front(), 0u);
  EXPECT_EQ(g.offsets.back(), g.points.size());
}

TEST(Boundaries, EmptyAndFlatImagesGiveNoGroups) {
  TernaryImage t{5, 5, std::vector<std::uint8_t>(25, kTernaryUnknown)};
  EXPECT_EQ(group_boundaries(t, connected_components(t)).count(), 0u);
  TernaryImage e;
  EXPECT_EQ(group_boundaries(e, connected_components(e)).count(), 0u);
}
