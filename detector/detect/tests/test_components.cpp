#include <gtest/gtest.h>

#include "detect/components.hpp"

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
std::uint32_t lab(const Components& c, int x, int y) { return c.label[static_cast<std::size_t>(y * c.width + x)]; }
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
