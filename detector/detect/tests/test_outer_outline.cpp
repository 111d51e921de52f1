#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "detect/outer_outline.hpp"
#include "detect/quad_fit.hpp"
#include "detect/threshold_quads.hpp"

namespace test_outer_outline {

using namespace tagbench;

namespace {
// A square outline in doubled coordinates: centre c2, half side half2; sign +1 steps toward the light
// side point outward (a dark square on light ground), -1 inward.
void outline(std::vector<BoundaryPoint>& pts, int c2, int half2, int sign) {
  for (int t = -half2; t < half2; ++t) {
    pts.push_back({c2 + t, c2 - half2, 0, static_cast<std::int8_t>(-sign)});  // top
    pts.push_back({c2 + half2, c2 + t, static_cast<std::int8_t>(sign), 0});   // right
    pts.push_back({c2 - t, c2 + half2, 0, static_cast<std::int8_t>(sign)});   // bottom
    pts.push_back({c2 - half2, c2 - t, static_cast<std::int8_t>(-sign), 0});  // left
  }
}
int chebyshev(const BoundaryPoint& p, int c2) { return std::max(std::abs(p.x2 - c2), std::abs(p.y2 - c2)); }
// Each corner of the 20 px square 30..50 has a corner of `q` within 0.6 px.
void expect_square_30_50(const Corners& q) {
  const Corners truth = {Eigen::Vector2d(30, 30), Eigen::Vector2d(50, 30), Eigen::Vector2d(50, 50),
                         Eigen::Vector2d(30, 50)};
  for (std::size_t i = 0; i < 4; ++i) {
    double best = 1e9;
    for (const auto& c : q) best = std::min(best, (c - truth[i]).norm());
    EXPECT_LT(best, 0.6) << "corner " << i;
  }
}
}  // namespace

// angle_bin is the atan2f formula's bin, exactly: on the half-pixel lattice the outlines use (the
// centre on or between lattice points), on random offsets, on the axes and at the centre, for the
// default 96 bins and others. The test counts the lattice points that sit within 1e-3 of a bin's edge
// (where the polynomial alone could be wrong), so it fails if none is ever tried.
TEST(OuterOutline, AngleBinIsTheAtan2fBin) {
  const auto reference = [](float dx, float dy, int bins, float per_radian) {
    const float a = std::atan2(dy, dx) + std::numbers::pi_v<float>;
    return std::min(bins - 1, static_cast<int>(a * per_radian));
  };
  int near_edge = 0;
  for (const int bins : {8, 96, 97, 1024}) {
    const float per_radian = static_cast<float>(bins) / (2 * std::numbers::pi_v<float>);
    for (const float off : {0.0f, 0.5f, 0.25f})
      for (int y = -130; y <= 130; ++y)
        for (int x = -130; x <= 130; ++x) {
          const float dx = static_cast<float>(x) - off, dy = static_cast<float>(y) - off;
          ASSERT_EQ(angle_bin(dx, dy, bins, per_radian), reference(dx, dy, bins, per_radian)) << dx << ", " << dy;
          const double t = (std::atan2(static_cast<double>(dy), static_cast<double>(dx)) + std::numbers::pi) * bins /
                           (2 * std::numbers::pi);
          near_edge += std::abs(t - std::round(t)) < 1e-3;
        }
    std::uint64_t r = 12345;  // a fixed LCG: random-looking offsets, the same every run
    for (int i = 0; i < 200000; ++i) {
      r = r * 6364136223846793005ULL + 1442695040888963407ULL;
      const float dx = static_cast<float>(static_cast<int>(r >> 40) % 20001 - 10000) / 37.0f;
      const float dy = static_cast<float>(static_cast<int>((r >> 16) & 0xFFFFFF) % 20001 - 10000) / 41.0f;
      ASSERT_EQ(angle_bin(dx, dy, bins, per_radian), reference(dx, dy, bins, per_radian)) << dx << ", " << dy;
    }
  }
  EXPECT_GT(near_edge, 100);
  // Zeros of either sign and infinities take the formula itself (a NaN, which the outlines' integer
  // coordinates cannot give, would make the formula's float-to-int conversion undefined).
  const float inf = std::numeric_limits<float>::infinity();
  for (const float dx : {0.0f, -0.0f, 1.0f, -1.0f, inf, -inf})
    for (const float dy : {0.0f, -0.0f, 1.0f, -1.0f, inf, -inf}) {
      const float per_radian = 96.0f / (2 * std::numbers::pi_v<float>);
      EXPECT_EQ(angle_bin(dx, dy, 96, per_radian), reference(dx, dy, 96, per_radian)) << dx << ", " << dy;
    }
}

// A square's edge (20 px, outward steps), the payload's inner edges at 3/4 of the way out (outward
// steps too, as where a leaking white ring meets the border's inside) and a ring's outer edge (inward
// steps): only the square's edge is kept, most of it.
TEST(OuterOutline, KeepsTheSquaresEdgeAndDropsInnerEdgesAndTheRingsOuterEdge) {
  std::vector<BoundaryPoint> group;
  outline(group, 80, 20, 1);
  outline(group, 80, 15, 1);
  outline(group, 80, 26, -1);
  OuterOutlineScratch s;
  std::vector<BoundaryPoint> out;
  outer_outline_points(group, {}, s, out);
  ASSERT_FALSE(out.empty());
  for (const auto& p : out) EXPECT_EQ(chebyshev(p, 80), 20);
  EXPECT_GE(out.size(), 140u);  // of 160: a few next to the corners fall under the widened envelope
  EXPECT_LE(out.size(), 160u);
}

// Nothing outward: nothing kept (a light square on dark ground is not this stage's business).
TEST(OuterOutline, KeepsNothingWithoutOutwardPoints) {
  std::vector<BoundaryPoint> group;
  outline(group, 80, 20, -1);
  OuterOutlineScratch s;
  std::vector<BoundaryPoint> out = {BoundaryPoint{}};
  outer_outline_points(group, {}, s, out);
  EXPECT_TRUE(out.empty());
}

// Fewer outward points than the caller's minimum: nothing kept (no quad could be fitted to them);
// at the minimum, the outline as without one.
TEST(OuterOutline, KeepsNothingWhenTooFewPointsFaceOutward) {
  std::vector<BoundaryPoint> group;
  outline(group, 80, 20, 1);  // 160 outward points
  outline(group, 80, 26, -1);
  OuterOutlineScratch s;
  std::vector<BoundaryPoint> all, out = {BoundaryPoint{}};
  outer_outline_points(group, {}, s, all);
  outer_outline_points(group, {}, s, out, 161);
  EXPECT_TRUE(out.empty());
  outer_outline_points(group, {}, s, out, 160);
  ASSERT_EQ(out.size(), all.size());
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].x2, all[i].x2);
}

// In fit_quads: the mixed group's own fit is the mean of its two nested outlines (each side's line
// passes between them within max_line_fit_mse: the bent quad of a tag whose white ring leaks into its
// payload); refit_outer_outline adds the square itself as a second candidate.
TEST(OuterOutline, FitQuadsAddsTheSquareOfAGroupWithInnerEdges) {
  BoundaryGroups groups;
  outline(groups.points, 80, 20, 1);
  outline(groups.points, 80, 12, 1);
  groups.offsets = {0, static_cast<std::uint32_t>(groups.points.size())};
  const ImageF img(80, 80, 0.5f);
  const Corners truth = {Eigen::Vector2d(30, 30), Eigen::Vector2d(50, 30), Eigen::Vector2d(50, 50),
                         Eigen::Vector2d(30, 50)};
  auto error = [&](const Corners& q) {
    double e = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      double best = 1e9;
      for (const auto& c : q) best = std::min(best, (c - truth[i]).norm());
      e = std::max(e, best);
    }
    return e;
  };
  QuadFitScratch s;
  QuadFitOptions opt;
  std::vector<Quad> quads;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_GT(error(quads[0].corners), 1.5);
  quads.clear();
  opt.refit_outer_outline = true;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 2u);
  EXPECT_GT(error(quads[0].corners), 1.5);
  EXPECT_LT(error(quads[1].corners), 0.6);
}

namespace {
// The group of the tests below: a 20 px square (30..50) whose
// own fit fails, its outline's fit succeeds.
BoundaryGroups square_with_inner_cell() {
  BoundaryGroups groups;
  outline(groups.points, 80, 20, 1);
  std::vector<BoundaryPoint> cell;
  outline(cell, 0, 10, 1);
  for (auto p : cell) groups.points.push_back({p.x2 + 74, p.y2 + 74, p.gx, p.gy});
  groups.offsets = {0, static_cast<std::uint32_t>(groups.points.size())};
  return groups;
}
}  // namespace

// Inner edges far inside (a payload cell's outline, off the centre): the group's own fit fails (no
// line fits a run that holds both), and the outline is then the quad.
TEST(OuterOutline, FitQuadsFallsBackOnTheOutlineWhenTheGroupFitsNoQuad) {
  const BoundaryGroups groups = square_with_inner_cell();
  const ImageF img(80, 80, 0.5f);
  QuadFitScratch s;
  QuadFitOptions opt;
  std::vector<Quad> quads;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_TRUE(quads.empty());
  opt.refit_outer_outline = true;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 1u);
  expect_square_30_50(quads[0].corners);
}

// A clean square's group: one quad, no second candidate (the outline drops nothing that matters).
TEST(OuterOutline, ACleanSquareGivesOneQuad) {
  BoundaryGroups groups;
  outline(groups.points, 80, 20, 1);
  groups.offsets = {0, static_cast<std::uint32_t>(groups.points.size())};
  const ImageF img(80, 80, 0.5f);
  QuadFitScratch s;
  QuadFitOptions opt;
  opt.refit_outer_outline = true;
  opt.outer.min_dropped = 0;  // even when the outline is always refitted
  std::vector<Quad> quads;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_EQ(quads.size(), 1u);
}

namespace {
// An 80 x 80 image: light ground (0.3 + step), the square 30..50 dark (0.3); blank: no square.
ImageF ringed_square(float step, bool blank = false) {
  ImageF img(80, 80, 0.3f + step);
  if (!blank)
    for (int y = 30; y <= 50; ++y)
      for (int x = 30; x <= 50; ++x) img.at(x, y) = 0.3f;
  return img;
}
}  // namespace

// Groups larger than max_size_px are not tried (the group's box is 20 px).
TEST(OuterOutline, MaxSizeSkipsLargerGroups) {
  const BoundaryGroups groups = square_with_inner_cell();
  const ImageF img(80, 80, 0.5f);
  QuadFitScratch s;
  QuadFitOptions opt;
  opt.refit_outer_outline = true;
  std::vector<Quad> quads;
  opt.outer.max_size_px = 19;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_TRUE(quads.empty());
  opt.outer.max_size_px = 21;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_EQ(quads.size(), 1u);
}

// The points-per-length gate: the group (box 20 x 20 px) is tried only when it holds at least
// min_points_per_box_px points per px of its box's width plus height.
TEST(OuterOutline, PointsPerBoxGateSkipsSparseGroups) {
  const BoundaryGroups groups = square_with_inner_cell();
  const double ratio = static_cast<double>(groups.points.size()) / 40.0;
  const ImageF img(80, 80, 0.5f);
  QuadFitScratch s;
  QuadFitOptions opt;
  opt.refit_outer_outline = true;
  std::vector<Quad> quads;
  opt.outer.min_points_per_box_px = 0.999 * ratio;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_EQ(quads.size(), 1u);
  quads.clear();
  opt.outer.min_points_per_box_px = 1.001 * ratio;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_TRUE(quads.empty());
}

// The ring check: a dark square on a lighter ground passes, the same corners on a flat image or with
// the ring darker than the square fail, and a step below ring_min_step fails.
TEST(OuterOutline, RingCheckWantsADarkSquareInsideALightRing) {
  const Corners q = {Eigen::Vector2d(30, 30), Eigen::Vector2d(50, 30), Eigen::Vector2d(50, 50),
                     Eigen::Vector2d(30, 50)};
  OuterOutlineOptions opt;
  EXPECT_TRUE(outline_has_ring(q, ringed_square(0.1f), opt));
  EXPECT_FALSE(outline_has_ring(q, ringed_square(0.1f, true), opt));
  EXPECT_FALSE(outline_has_ring(q, ringed_square(-0.1f), opt));  // light square on a dark ground
  EXPECT_TRUE(outline_has_ring(q, ringed_square(4.0f / 255), opt));
  opt.ring_min_step = 5.0 / 255;
  EXPECT_FALSE(outline_has_ring(q, ringed_square(4.0f / 255), opt));
  // The corners' order around the square does not matter (either direction, any start).
  opt = {};
  const Corners r = {q[2], q[1], q[0], q[3]};
  EXPECT_TRUE(outline_has_ring(r, ringed_square(0.1f), opt));
}

// ring_outward_slack: a quad whose right side lies 2 px inside the square's edge, where a light
// payload cell lies 2-5 px inside (a blurred 1-cell border the threshold cut into): the pairs of that
// side step down, and the check refuses the quad; read also 1/16 of the width (1.25 px) further out,
// they reach the border and the ring, and it passes. A flat image still fails with the slack.
TEST(OuterOutline, RingCheckSlackReadsASideLeftInsideTheEdge) {
  ImageF img = ringed_square(0.2f);  // dark square 30..50 on a lighter ground
  for (int y = 33; y <= 47; ++y)
    for (int x = 44; x <= 47; ++x) img.at(x, y) = 0.6f;  // the light cell behind the right border
  const Corners q = {Eigen::Vector2d(30, 30), Eigen::Vector2d(48, 30), Eigen::Vector2d(48, 50),
                     Eigen::Vector2d(30, 50)};
  OuterOutlineOptions opt;
  EXPECT_FALSE(outline_has_ring(q, img, opt));
  opt.ring_outward_slack = 1.0 / 16;
  EXPECT_TRUE(outline_has_ring(q, img, opt));
  EXPECT_FALSE(outline_has_ring(q, ringed_square(0.2f, true), opt));
  EXPECT_FALSE(outline_has_ring(q, ringed_square(-0.2f), opt));  // light square on a dark ground
  // ring_slack_sides: this quad needs the slack on one side only.
  opt.ring_slack_sides = 0;
  EXPECT_FALSE(outline_has_ring(q, img, opt));
  opt.ring_slack_sides = 1;
  EXPECT_TRUE(outline_has_ring(q, img, opt));
}

// A dark bar 21 x 5 px in a lighter ground has its ring, but is no tag seen at up to 70 degrees:
// min_side_ratio (shortest / longest side) refuses it.
TEST(OuterOutline, RingCheckRefusesASliver) {
  ImageF img(80, 80, 0.4f);
  for (int y = 30; y <= 34; ++y)
    for (int x = 30; x <= 50; ++x) img.at(x, y) = 0.3f;
  const Corners q = {Eigen::Vector2d(29.5, 29.5), Eigen::Vector2d(50.5, 29.5), Eigen::Vector2d(50.5, 34.5),
                     Eigen::Vector2d(29.5, 34.5)};
  OuterOutlineOptions opt;
  opt.min_side_ratio = 0;
  EXPECT_TRUE(outline_has_ring(q, img, opt));
  opt.min_side_ratio = 0.3;  // 5 / 21 = 0.24
  EXPECT_FALSE(outline_has_ring(q, img, opt));
  opt.min_side_ratio = 0.2;
  EXPECT_TRUE(outline_has_ring(q, img, opt));
}

// In fit_quads: with ring_check the outline's quad is kept on a ringed square and dropped on a flat image.
TEST(OuterOutline, FitQuadsDropsOutlineQuadsWithoutARing) {
  const BoundaryGroups groups = square_with_inner_cell();
  QuadFitScratch s;
  QuadFitOptions opt;
  opt.refit_outer_outline = true;
  opt.outer.ring_check = true;
  std::vector<Quad> quads;
  fit_quads(groups, ringed_square(0.1f), opt, s, quads);
  EXPECT_EQ(quads.size(), 1u);
  quads.clear();
  fit_quads(groups, ringed_square(0.1f, true), opt, s, quads);
  EXPECT_TRUE(quads.empty());
}

// At half resolution the refit runs only when asked (outer.at_half_resolution), and its size limit is
// in half-resolution pixels there.
TEST(OuterOutline, HalfResolutionRunsTheRefitOnlyWhenAsked) {
  QuadFitOptions fit;
  fit.refit_outer_outline = true;
  fit.outer.max_size_px = 50;
  fit.min_tag_width = 10;
  const QuadFitOptions full = quad_fit_options_for(fit, false);
  EXPECT_TRUE(full.refit_outer_outline);
  EXPECT_EQ(full.outer.max_size_px, 50);
  EXPECT_EQ(full.min_tag_width, 10);
  const QuadFitOptions half = quad_fit_options_for(fit, true);
  EXPECT_FALSE(half.refit_outer_outline);
  EXPECT_EQ(half.outer.max_size_px, 25);
  EXPECT_EQ(half.min_tag_width, 5);
  fit.outer.at_half_resolution = true;
  EXPECT_TRUE(quad_fit_options_for(fit, true).refit_outer_outline);
  fit.min_tag_width = 4;
  EXPECT_EQ(quad_fit_options_for(fit, true).min_tag_width, 3);
}

namespace {
// A 20 px square (30..50, Chebyshev distance 10 from (40, 40)) whose black border ran into a darker
// plate round its paper: the square's edge (outward steps), the plate's inner edge at 12 px (inward)
// and its outer edge at 15 px (outward), one group.
BoundaryGroups square_leaked_into_plate() {
  BoundaryGroups groups;
  outline(groups.points, 80, 20, 1);
  outline(groups.points, 80, 24, -1);
  outline(groups.points, 80, 30, 1);
  groups.offsets = {0, static_cast<std::uint32_t>(groups.points.size())};
  return groups;
}
// Its image: square 0.1, white ring 0.6, plate 0.3, ground 0.8 but dark (0.1) left of the plate (a
// shadow or a line touching it: the plate's outline has no lighter ring on that side).
ImageF plate_image() {
  ImageF img(80, 80, 0.8f);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const int d = std::max(std::abs(x - 40), std::abs(y - 40));
      img.at(x, y) = d <= 10 ? 0.1f : d <= 12 ? 0.6f : d <= 15 ? 0.3f : x < 25 ? 0.1f : 0.8f;
    }
  return img;
}
}  // namespace

// The innermost outward points of that group are the square's edge; the outermost, the plate's.
TEST(OuterOutline, InnermostOutlineIsTheSquaresEdge) {
  const BoundaryGroups groups = square_leaked_into_plate();
  OuterOutlineScratch s;
  std::vector<BoundaryPoint> outer, inner = {BoundaryPoint{}};
  EXPECT_EQ(inner_outline_points({}, s, inner), 0u);  // no outline computed yet
  EXPECT_TRUE(inner.empty());
  outer_outline_points(groups.group(0), {}, s, outer);
  ASSERT_FALSE(outer.empty());
  for (const auto& p : outer) EXPECT_EQ(chebyshev(p, 80), 30);
  EXPECT_EQ(inner_outline_points({}, s, inner), 0u);
  ASSERT_GE(inner.size(), 140u);
  for (const auto& p : inner) EXPECT_EQ(chebyshev(p, 80), 20);
  // Outward points that do not surround the centre (here: all bins asked for, one more than there
  // are): nothing.
  OuterOutlineOptions all_bins;
  all_bins.innermost_min_coverage = 1.01;
  EXPECT_EQ(inner_outline_points(all_bins, s, inner), 0u);
  EXPECT_TRUE(inner.empty());
  // Only two sides of the square (a corner of texture): about half of the bins, under the default 0.75.
  std::vector<BoundaryPoint> corner;
  for (const auto& p : groups.group(0))
    if (chebyshev(p, 80) == 20 && (p.x2 < 80 - 10 || p.y2 < 80 - 10) && p.gx + p.gy < 0) corner.push_back(p);
  ASSERT_FALSE(corner.empty());
  outer_outline_points(corner, {}, s, outer);
  ASSERT_FALSE(outer.empty());
  EXPECT_EQ(inner_outline_points({}, s, inner), 0u);
  EXPECT_TRUE(inner.empty());
  // A plain square: most innermost points are outermost too (fit_quads then skips the refit).
  BoundaryGroups plain;
  outline(plain.points, 80, 20, 1);
  outer_outline_points(plain.points, {}, s, outer);
  const std::size_t both = inner_outline_points({}, s, inner);
  EXPECT_GE(static_cast<double>(both), 0.8 * static_cast<double>(inner.size()));
}

// In fit_quads: the group's own fit fails (tight max_line_fit_mse: no line passes near all three
// outlines), the outermost outline's quad is the plate, refused by the ring check; with innermost the
// square is the quad.
TEST(OuterOutline, FitQuadsFallsBackOnTheInnermostOutline) {
  const BoundaryGroups groups = square_leaked_into_plate();
  const ImageF img = plate_image();
  QuadFitScratch s;
  QuadFitOptions opt;
  opt.max_line_fit_mse = 1.0;
  opt.refit_outer_outline = true;
  opt.outer.ring_check = true;
  opt.outer.ring_min_share = 1.0;
  std::vector<Quad> quads;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_TRUE(quads.empty());
  opt.outer.innermost = true;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 1u);
  expect_square_30_50(quads[0].corners);
  // Without the ring check the plate's quad is taken and the innermost outline is not tried.
  quads.clear();
  opt.outer.ring_check = false;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_GT((quads[0].corners[0] - Eigen::Vector2d(40, 40)).norm(), 20.0);
}

}  // namespace test_outer_outline
