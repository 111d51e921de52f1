#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/dark_outlines.hpp"
#include "detect/detector.hpp"
#include "detect/payload_decode.hpp"
#include "detect/threshold.hpp"
#include "synthetic_tag.hpp"

namespace test_dark_outlines {

using namespace tagbench;

namespace {

// A dark square (side 24 px at (40, 40)) in a light ring 3 px wide on a dark card, the ring cut at the
// middle of its top and bottom sides by dark bridges 3 px wide: the ring falls into two light
// components, so the square's outline is split between two boundary groups (each also holding half
// of the card's inner edge), while the square, the bridges and the card are one dark component.
// The bridges are darker than the square (0.05). off_middle: they cut the ring 6 px left of the
// sides' middles, so the border pre-filter, which samples each side's middle, sees the ring light
// outside all four sides.
ImageF broken_ring_image(bool off_middle = false) {
  ImageF img(80, 80, 0.2f);
  const double bx = off_middle ? 34.0 : 40.0;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const double dx = std::abs(x - 40.0), dy = std::abs(y - 40.0), d = std::max(dx, dy);
      const bool bridge = std::abs(x - bx) <= 1 && dy > 12;
      if (d <= 12) img.at(x, y) = 0.1f;
      else if (d <= 15 && !bridge) img.at(x, y) = 0.8f;
      else if (d <= 15) img.at(x, y) = 0.05f;
    }
  return img;
}

using Pass = synth::ThresholdPass;

// The largest distance from a corner of q to the nearest corner of the square.
double corner_error(const Quad& q, const Corners& want) {
  double worst = 0;
  for (const auto& c : q.corners) {
    double best = 1e9;
    for (const auto& w : want) best = std::min(best, (c - w).norm());
    worst = std::max(worst, best);
  }
  return worst;
}

// The quad within 1 px of the black square at every corner (its pixel centres 28..52, so its edges at
// 27.5 and 52.5), or null.
const Quad* square_quad(const std::vector<Quad>& quads) {
  const Corners want = synth::square_tag_corners(40, 40, 25, 0);
  for (const Quad& q : quads)
    if (corner_error(q, want) < 1.0) return &q;
  return nullptr;
}
bool finds_square(const std::vector<Quad>& quads) { return square_quad(quads) != nullptr; }

}  // namespace

// No group alone outlines the square; the dark component's groups joined do.
TEST(DarkOutlines, JoinsTheGroupsOfABrokenRing) {
  const ImageF img = broken_ring_image();
  Pass p(img);
  const DetectorOptions o;
  QuadFitScratch fs;
  std::vector<Quad> own;
  fit_quads(p.groups, img, o.threshold_quads.fit, fs, own);
  EXPECT_FALSE(finds_square(own));
  DarkOutlineScratch s;
  const DarkOutlineOptions on{.enabled = true};
  EXPECT_TRUE(finds_square(dark_outline_quads(p.groups, p.comp, img, {}, o.threshold_quads.fit,
                                              o.threshold_quads.refine, on, fs, s)));
  // Off, too large a box for max_size_px, or centred inside a tag already found: nothing there.
  EXPECT_TRUE(dark_outline_quads(p.groups, p.comp, img, {}, o.threshold_quads.fit, o.threshold_quads.refine,
                                 DarkOutlineOptions{}, fs, s)
                  .empty());
  EXPECT_FALSE(finds_square(dark_outline_quads(p.groups, p.comp, img, {}, o.threshold_quads.fit,
                                               o.threshold_quads.refine,
                                               DarkOutlineOptions{.enabled = true, .max_size_px = 20}, fs, s)));
  const std::vector<Corners> covered = {synth::square_tag_corners(40, 40, 25, 0)};
  EXPECT_FALSE(finds_square(dark_outline_quads(p.groups, p.comp, img, covered, o.threshold_quads.fit,
                                               o.threshold_quads.refine, on, fs, s)));
}

// check_before_refining: a quad the border pre-filter refuses (the bridges at the middles of two
// sides, darker outside than in: only two sides pass) is left as fitted, not refined; one it admits
// (the bridges off the middles), or its test with slack admits, is refined as without the check.
TEST(DarkOutlines, ThePreFilterBeforeRefiningLeavesRefusedQuadsAsFitted) {
  const DetectorOptions o;
  const ThresholdQuadOptions::RefineCheck pre{.enabled = true, .payload_width = 6, .min_contrast = 0.02};
  const DarkOutlineOptions plain{.enabled = true}, checked{.enabled = true, .check_before_refining = true},
      slack{.enabled = true, .check_before_refining = true, .slack_sides = 3};
  const auto quads = [&](const ImageF& img, const DarkOutlineOptions& opt) {
    Pass p(img);
    QuadFitScratch fs;
    DarkOutlineScratch s;
    return dark_outline_quads(p.groups, p.comp, img, {}, o.threshold_quads.fit, o.threshold_quads.refine, opt, fs, s,
                              pre);
  };
  const ImageF two_cuts = broken_ring_image();
  const auto refined = quads(two_cuts, plain), fitted = quads(two_cuts, checked);
  const Quad *r = square_quad(refined), *f = square_quad(fitted);
  ASSERT_TRUE(r && f);
  EXPECT_FALSE(border_contrast_plausible(two_cuts, r->corners, 6, 0.02));
  EXPECT_FALSE(border_contrast_plausible(two_cuts, f->corners, 6, 0.02));
  double moved = 0;  // the refinement moved the corners; the checked run left them as fitted
  for (std::size_t k = 0; k < 4; ++k) moved = std::max(moved, (f->corners[k] - r->corners[k]).norm());
  EXPECT_GT(moved, 1e-6);
  // The slack test reaches past the 3 px ring to the card, lighter than the square: it admits the
  // quad, which is then refined as without the check.
  ASSERT_TRUE(border_contrast_plausible_with_slack(two_cuts, f->corners, 6, 0.02, 3));
  const auto with_slack = quads(two_cuts, slack);
  ASSERT_TRUE(square_quad(with_slack));
  EXPECT_EQ(square_quad(with_slack)->corners, r->corners);
  const ImageF off = broken_ring_image(true);
  EXPECT_TRUE(border_contrast_plausible(off, synth::square_tag_corners(40, 40, 25, 0), 6, 0.02));
  const auto a = quads(off, plain), b = quads(off, checked);
  ASSERT_TRUE(square_quad(a) && square_quad(b));
  EXPECT_EQ(square_quad(a)->corners, square_quad(b)->corners);
}

// A black border 3 px wide (the square's edges at 27.5 and 52.5 px) broken at the top near its right
// end and at the bottom near its left end, on a light ground that runs into the square's light
// inside through both gaps: two dark pieces, each one group with the ground, whose boxes overlap.
// Ten dark dots round it border the same light ground, so that ground has 12 groups, too many to join
// whole (max_groups 8).
ImageF broken_border_image() {
  ImageF img(80, 80, 0.8f);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const int d = std::max(std::abs(x - 40), std::abs(y - 40));
      const bool gap = (y < 40 && x >= 45 && x <= 47) || (y > 40 && x >= 33 && x <= 35);
      if (d >= 10 && d <= 12 && !gap) img.at(x, y) = 0.1f;
    }
  for (int k = 0; k < 10; ++k) {  // 5 x 5 dots on a ring 22 px out
    const double a = 2 * 3.14159265358979 * k / 10;
    const int cx = 40 + static_cast<int>(std::lround(22 * std::cos(a))), cy = 40 + static_cast<int>(std::lround(22 * std::sin(a)));
    for (int y = cy - 2; y <= cy + 2; ++y)
      for (int x = cx - 2; x <= cx + 2; ++x) img.at(x, y) = 0.1f;
  }
  return img;
}

// The broken border's threshold pass, with the default profile's fit and refinement options.
class BrokenBorder : public ::testing::Test {
 protected:
  const ImageF img = broken_border_image();
  Pass p{img};
  const QuadFitOptions fit = DetectorOptions{}.threshold_quads.fit;
  const EdgeRefineOptions refine = DetectorOptions{}.threshold_quads.refine;
  QuadFitScratch fs;
  DarkOutlineScratch s;
};

// overlap_clusters: the two pieces, in no joinable component (each dark piece has one group; the light
// ground has twelve), are joined by their overlapping boxes, and their outline is the square's; no
// group alone gives it.
TEST_F(BrokenBorder, OverlapClustersJoinABorderBrokenInTwo) {
  const auto found = [&](const DarkOutlineOptions& opt) {
    return finds_square(dark_outline_quads(p.groups, p.comp, img, {}, fit, refine, opt, fs, s));
  };
  std::vector<Quad> own;
  fit_quads(p.groups, img, fit, fs, own);
  EXPECT_FALSE(finds_square(own));
  EXPECT_FALSE(found(DarkOutlineOptions{.enabled = true}));
  EXPECT_TRUE(found(DarkOutlineOptions{.enabled = true, .overlap_clusters = true}));
  // The dots stay apart (their boxes overlap nothing): no joined outline but the square's.
  EXPECT_EQ(s.joined.count(), 1u);
}

// failed_pairs: the same two pieces, each of which gives no quad alone (fit_quads' gave_quad), joined
// as a pair by their boxes without the overlap clusters; without the flags (or with every group
// marked as having given a quad) no pair is joined.
TEST_F(BrokenBorder, FailedPairsJoinTwoPiecesThatGaveNoQuad) {
  std::vector<Quad> own;
  std::vector<std::uint8_t> gave;
  fit_quads(p.groups, img, fit, fs, own, &gave);
  ASSERT_EQ(gave.size(), p.groups.count());
  EXPECT_FALSE(finds_square(own));
  std::size_t failed = 0;
  for (std::uint8_t g : gave) failed += g == 0;
  EXPECT_GE(failed, 2u);
  const DarkOutlineOptions pairs{.enabled = true, .failed_pairs = true};
  const auto found = [&](std::span<const std::uint8_t> flags, const DarkOutlineOptions& opt) {
    return finds_square(dark_outline_quads(p.groups, p.comp, img, {}, fit, refine, opt, fs, s, {}, flags));
  };
  EXPECT_TRUE(found(gave, pairs));
  EXPECT_FALSE(found({}, pairs));
  EXPECT_FALSE(found(gave, DarkOutlineOptions{.enabled = true}));
  const std::vector<std::uint8_t> all_gave(gave.size(), 1);
  EXPECT_FALSE(found(all_gave, pairs));
  // A pair whose joined box is larger than max_size_px is not joined.
  EXPECT_FALSE(found(gave, DarkOutlineOptions{.enabled = true, .max_size_px = 20, .failed_pairs = true}));
  // Each piece is about the square's size (share near 1) with far more than 24 points: the filters
  // keep the pair; a share above 1 or more points than any group has drop it.
  EXPECT_TRUE(found(gave, DarkOutlineOptions{.enabled = true, .failed_pairs = true, .pair_min_points = 24,
                                             .pair_min_share = 0.5}));
  EXPECT_FALSE(found(gave, DarkOutlineOptions{.enabled = true, .failed_pairs = true, .pair_min_points = 100000}));
  EXPECT_FALSE(found(gave, DarkOutlineOptions{.enabled = true, .failed_pairs = true, .pair_min_share = 1.01}));
}

TEST(DarkOutlines, ComponentsOfAnotherImageAreRefused) {
  const ImageF img = broken_ring_image();
  Pass p(img);
  QuadFitScratch fs;
  DarkOutlineScratch s;
  EXPECT_THROW(dark_outline_quads(p.groups, p.comp, ImageF(40, 40, 0.5f), {}, QuadFitOptions{}, EdgeRefineOptions{},
                                  DarkOutlineOptions{.enabled = true}, fs, s),
               std::invalid_argument);
}

// The default and thorough profiles join the outlines; the paper's does not.
TEST(DarkOutlines, InTheDefaultAndThoroughProfilesNotThePapers) {
  EXPECT_TRUE(DetectorOptions{}.dark_outlines.enabled);
  EXPECT_TRUE(DetectorOptions{}.dark_outlines.check_before_refining);
  EXPECT_EQ(DetectorOptions{}.dark_outlines.slack_sides, 3);
  EXPECT_FALSE(DetectorOptions::paper().dark_outlines.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().dark_outlines.enabled);
}

}  // namespace test_dark_outlines
