#include <gtest/gtest.h>

#include <algorithm>
#include <queue>
#include <random>

#include "detect/components.hpp"

namespace test_components {

using namespace tagbench;

namespace {
TernaryImage from_rows(const std::vector<std::string>& rows) {  // '#' dark, '.' light, '?' unknown
  TernaryImage t;
  t.height = static_cast<int>(rows.size());
  t.width = static_cast<int>(rows[0].size());
  for (const auto& r : rows)
    for (char c : r) t.data.push_back(c == '#' ? kTernaryDark : c == '.' ? kTernaryLight : kTernaryUnknown);
  return t;
}
std::uint32_t lab(const Components& c, int x, int y) { return c.label_at(x, y); }
}  // namespace

TEST(Components, DarkIsFourConnectedLightIsEightConnected) {
  // Two dark pixels touching only diagonally are two components; the light pixels around them,
  // also touching diagonally through the middle, are one.
  const auto t = from_rows({"#.",
                            ".#"});
  const Components c = connected_components(t);
  EXPECT_NE(lab(c, 0, 0), lab(c, 1, 1));
  EXPECT_EQ(lab(c, 1, 0), lab(c, 0, 1));
  EXPECT_EQ(c.count, 3u);
  EXPECT_EQ(c.size[lab(c, 1, 0)], 2u);
  EXPECT_EQ(c.size[lab(c, 0, 0)], 1u);
}

TEST(Components, DarkEightSwapsTheConnectivity) {
  // The same pattern with dark_eight: the diagonal dark pixels join, the light ones do not.
  const auto t = from_rows({"#.",
                            ".#"});
  const Components c = connected_components(t, true);
  EXPECT_EQ(lab(c, 0, 0), lab(c, 1, 1));
  EXPECT_NE(lab(c, 1, 0), lab(c, 0, 1));
  EXPECT_EQ(c.count, 3u);
  EXPECT_EQ(c.size[lab(c, 0, 0)], 2u);
  // A one-pixel diagonal staircase (a rotated thin border) is one dark component, the light pixels
  // on its two sides are two.
  const auto s = from_rows({"#...",
                            ".#..",
                            "..#.",
                            "...#"});
  const Components d = connected_components(s, true);
  EXPECT_EQ(lab(d, 0, 0), lab(d, 3, 3));
  EXPECT_NE(lab(d, 1, 0), lab(d, 0, 1));
  EXPECT_EQ(d.count, 3u);
  const Components d4 = connected_components(s);
  EXPECT_NE(lab(d4, 0, 0), lab(d4, 3, 3));
}

TEST(Components, UShapeJoinsThroughALaterRowAndSizesAddUp) {
  const auto t = from_rows({"#.#..",
                            "#.#..",
                            "###.?",
                            ".....",
                            "?????"});
  const Components c = connected_components(t);
  EXPECT_EQ(lab(c, 0, 0), lab(c, 2, 0));  // the two arms meet in row 2
  EXPECT_EQ(c.size[lab(c, 0, 0)], 7u);
  EXPECT_EQ(lab(c, 1, 0), lab(c, 1, 1));  // the light inside the U
  EXPECT_NE(lab(c, 1, 0), lab(c, 3, 0));  // is cut off from the light outside (4-connected dark wall, no gap)
  EXPECT_EQ(lab(c, 3, 0), lab(c, 0, 3));  // the outer light wraps around below
  EXPECT_EQ(lab(c, 4, 2), kNoComponent);
  EXPECT_EQ(lab(c, 2, 4), kNoComponent);
  std::uint32_t total = 0;
  for (auto s : c.size) total += s;
  EXPECT_EQ(total, 25u - 6u);  // every classed pixel once
  EXPECT_EQ(c.count, 3u);
}

TEST(Components, LightLeaksThroughADiagonalGapOfTheDarkWall) {
  const auto t = from_rows({"#..",
                            ".#.",
                            "..#"});
  const Components c = connected_components(t);
  EXPECT_EQ(lab(c, 1, 0), lab(c, 0, 1));  // light 8-connected across the diagonal wall
  EXPECT_NE(lab(c, 0, 0), lab(c, 1, 1));
}

// Against a breadth-first flood fill, on random images of runs 1-40 px long (so the runs' ends are
// found both in the 8-byte steps and in the byte-wise tail): the same partition into components,
// unknown pixels in none, and the sizes.
TEST(Components, EqualsAFloodFillOnRandomImages) {
  std::mt19937 rng(5);
  for (const int w : {1, 7, 8, 9, 53, 130})
    for (int trial = 0; trial < 4; ++trial) {
      const int h = 1 + static_cast<int>(rng() % 40);
      TernaryImage t;
      t.width = w;
      t.height = h;
      const std::uint8_t values[3] = {kTernaryDark, kTernaryLight, kTernaryUnknown};
      while (t.data.size() < static_cast<std::size_t>(w * h)) {
        const std::uint8_t v = values[rng() % 3];
        for (int n = 1 + static_cast<int>(rng() % 40); n > 0 && t.data.size() < static_cast<std::size_t>(w * h); --n)
          t.data.push_back(v);
      }
      const Components c = connected_components(t);
      const std::vector<std::uint32_t> label = label_image(c);
      for (int i = 0; i < w * h; ++i) ASSERT_EQ(c.label_at(i % w, i / w), label[static_cast<std::size_t>(i)]);
      // A component's id is its first run in raster order (the low-contrast look relies on it).
      for (std::uint32_t r = 0; r < c.runs.size(); ++r) {
        const std::uint32_t id = c.run_label[r];
        if (id == kNoComponent) continue;
        ASSERT_LE(id, r);
        ASSERT_EQ(c.run_label[id], id);
      }
      std::vector<int> bfs(t.data.size(), -1), bfs_size;
      for (int start = 0; start < w * h; ++start) {
        if (bfs[static_cast<std::size_t>(start)] >= 0 || t.data[static_cast<std::size_t>(start)] == kTernaryUnknown) continue;
        const int id = static_cast<int>(bfs_size.size());
        const std::uint8_t v = t.data[static_cast<std::size_t>(start)];
        const int reach = v == kTernaryLight ? 1 : 0;  // light also steps diagonally
        std::queue<int> q;
        q.push(start);
        bfs[static_cast<std::size_t>(start)] = id;
        int n = 0;
        while (!q.empty()) {
          const int p = q.front();
          q.pop();
          ++n;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              if ((dx != 0 && dy != 0 && !reach) || (dx == 0 && dy == 0)) continue;
              const int x = p % w + dx, y = p / w + dy;
              if (x < 0 || y < 0 || x >= w || y >= h) continue;
              const auto i = static_cast<std::size_t>(y * w + x);
              if (bfs[i] < 0 && t.data[i] == v) {
                bfs[i] = id;
                q.push(static_cast<int>(i));
              }
            }
        }
        bfs_size.push_back(n);
      }
      ASSERT_EQ(c.count, bfs_size.size());
      std::vector<std::uint32_t> label_of(bfs_size.size(), kNoComponent);
      for (std::size_t i = 0; i < t.data.size(); ++i) {
        if (bfs[i] < 0) {
          ASSERT_EQ(label[i], kNoComponent);
          continue;
        }
        auto& l = label_of[static_cast<std::size_t>(bfs[i])];
        if (l == kNoComponent) l = label[i];
        ASSERT_EQ(label[i], l) << "w " << w << " pixel " << i;
        ASSERT_EQ(c.size[l], static_cast<std::uint32_t>(bfs_size[static_cast<std::size_t>(bfs[i])]));
      }
      std::sort(label_of.begin(), label_of.end());
      EXPECT_EQ(std::adjacent_find(label_of.begin(), label_of.end()), label_of.end());  // distinct ids
    }
}

}  // namespace test_components
