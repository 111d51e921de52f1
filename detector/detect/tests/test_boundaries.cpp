#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/threshold.hpp"

namespace test_boundaries {

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

// The row scan (16 pixels at a time where it can) against the rule written out one pixel at a
// time: on random blotchy ternary images of widths around the 16-pixel blocks, the same points in
// the same order and the same groups.
TEST(Boundaries, FastScanMatchesThePixelByPixelRule) {
  std::mt19937 rng(11);
  for (const int W : {1, 2, 16, 17, 18, 33, 40, 64, 97}) {
    const int H = 23;
    TernaryImage t{W, H, std::vector<std::uint8_t>(static_cast<std::size_t>(W * H))};
    // Blotches: each 3x3 block of one class (so components are large enough), then speckle.
    std::uniform_int_distribution<int> cls(0, 2), speck(0, 9);
    const std::uint8_t values[3] = {kTernaryDark, kTernaryLight, kTernaryUnknown};
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) t.data[static_cast<std::size_t>(y * W + x)] = values[(x / 3 * 7 + y / 3 * 13) % 3];
    for (auto& v : t.data)
      if (speck(rng) == 0) v = values[cls(rng)];
    const auto c = connected_components(t);
    const auto label = label_image(c);
    BoundaryOptions opt;
    opt.min_component_pixels = 4;
    const auto g = group_boundaries(t, c, opt);
    // The reference: every pixel, its four forward neighbours, the shared diagonal point once.
    const auto big = [&](std::uint32_t id) { return id != kNoComponent && c.size[id] >= opt.min_component_pixels; };
    std::vector<std::pair<std::uint64_t, BoundaryPoint>> ref;
    for (int y = 0; y < H; ++y) {
      bool last_diag = false;
      for (int x = 0; x < W; ++x) {
        const std::uint8_t v0 = t.data[static_cast<std::size_t>(y * W + x)];
        const std::uint32_t l0 = label[static_cast<std::size_t>(y * W + x)];
        bool diag = false;
        const auto add = [&](int dx, int dy) {
          const int x1 = x + dx, y1 = y + dy;
          if (x1 < 0 || x1 >= W || y1 >= H || v0 == kTernaryUnknown || !big(l0)) return false;
          const std::uint8_t v1 = t.data[static_cast<std::size_t>(y1 * W + x1)];
          const std::uint32_t l1 = label[static_cast<std::size_t>(y1 * W + x1)];
          if (v0 + v1 != 255 || !big(l1)) return false;
          const int sign = v1 > v0 ? 1 : -1;
          ref.push_back({l0 < l1 ? (std::uint64_t{l1} << 32 | l0) : (std::uint64_t{l0} << 32 | l1),
                         BoundaryPoint{2 * x + dx, 2 * y + dy, static_cast<std::int8_t>(sign * dx), static_cast<std::int8_t>(sign * dy)}});
          return true;
        };
        add(1, 0);
        add(0, 1);
        if (!last_diag) add(-1, 1);
        diag = add(1, 1);
        last_diag = diag;
      }
    }
    // Grouped by pair in order of first appearance, scan order within a group.
    std::vector<std::uint64_t> order;
    for (const auto& [k, p] : ref)
      if (std::find(order.begin(), order.end(), k) == order.end()) order.push_back(k);
    std::vector<BoundaryPoint> want;
    std::vector<std::size_t> sizes;
    for (const auto k : order) {
      std::size_t n = 0;
      for (const auto& [kk, p] : ref)
        if (kk == k) want.push_back(p), ++n;
      sizes.push_back(n);
    }
    ASSERT_EQ(g.count(), order.size()) << "width " << W;
    ASSERT_EQ(g.points.size(), want.size()) << "width " << W;
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(g.points[i].x2, want[i].x2) << "width " << W << " point " << i;
      EXPECT_EQ(g.points[i].y2, want[i].y2) << "width " << W << " point " << i;
      EXPECT_EQ(g.points[i].gx, want[i].gx) << "width " << W << " point " << i;
      EXPECT_EQ(g.points[i].gy, want[i].gy) << "width " << W << " point " << i;
    }
    for (std::size_t k = 0; k < sizes.size(); ++k) EXPECT_EQ(g.group(k).size(), sizes[k]) << "width " << W;
  }
}

}  // namespace test_boundaries
