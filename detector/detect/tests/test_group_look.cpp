#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/group_look.hpp"
#include "detect/second_look.hpp"
#include "card_scene.hpp"
#include "detect/threshold.hpp"
#include "detect/threshold_quads.hpp"

namespace test_group_look {

using namespace tagbench;

namespace {
using tagbench::test_scenes::card_scene;
using tagbench::test_scenes::square_quad;
using tagbench::test_scenes::worst_corner_error;
BoundaryGroups groups_of(const ImageF& img) {
  ThresholdOptions th;
  th.min_contrast = 5.0f / 255.0f;
  const TernaryImage t = adaptive_threshold(img, th);
  const Components c = connected_components(t, true);
  return group_boundaries(t, c);
}
}  // namespace

// No quad was found there: the groups give one window (the others' centres fall inside it), at least
// min_window_px across, and the window's one-threshold look finds the 20 px square.
TEST(GroupLook, AWindowOnUncoveredGroupsFindsTheSquare) {
  const ImageF img = card_scene(0.30f, 0.42f, 0.31f, 20, 34, 27, 20);
  const BoundaryGroups g = groups_of(img);
  ASSERT_GT(g.count(), 0u);
  GroupLookOptions opt;
  opt.enabled = true;
  const std::vector<Quad> w = group_look_windows(g, {}, img.width, img.height, opt);
  ASSERT_EQ(w.size(), 1u);
  const Corners& c = w[0].corners;
  EXPECT_GE(c[2].x() - c[0].x(), opt.min_window_px);
  EXPECT_LE(c[0].x(), 26.5);
  EXPECT_GE(c[2].x(), 46.5);
  SecondLookOptions sl;
  sl.max_size_px = HUGE_VAL, sl.margin_px = 0, sl.inside_only = false;
  const auto quads = second_look_quads(img, w, {true}, ThresholdQuadOptions{}, sl);
  double best = HUGE_VAL;
  for (const Quad& q : quads) best = std::min(best, worst_corner_error(q.corners, square_quad(26.5, 46.5).corners));
  EXPECT_LT(best, 0.3);
}

// Groups inside a found quad's box, larger than max_size_px, with too few points, or with the unit off
// give no window.
TEST(GroupLook, RefusesCoveredLargeSparseOrDisabled) {
  const ImageF img = card_scene(0.30f, 0.42f, 0.31f, 20, 34, 27, 20);
  const BoundaryGroups g = groups_of(img);
  GroupLookOptions opt;
  opt.enabled = true;
  const Quad card = square_quad(19.5, 53.5);
  EXPECT_TRUE(group_look_windows(g, std::span(&card, 1), img.width, img.height, opt).empty());
  GroupLookOptions small = opt;
  small.max_size_px = 15;  // the card's group is 34 px, the square's 20 px
  EXPECT_TRUE(group_look_windows(g, {}, img.width, img.height, small).empty());
  GroupLookOptions sparse = opt;
  sparse.min_points = 100000;
  EXPECT_TRUE(group_look_windows(g, {}, img.width, img.height, sparse).empty());
  GroupLookOptions off = opt;
  off.enabled = false;
  EXPECT_TRUE(group_look_windows(g, {}, img.width, img.height, off).empty());
  GroupLookOptions none = opt;
  none.max_windows = 0;
  EXPECT_TRUE(group_look_windows(g, {}, img.width, img.height, none).empty());
}

}  // namespace test_group_look
