#include <gtest/gtest.h>

#include <stdexcept>

#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/dark_outlines.hpp"
#include "detect/detector.hpp"
#include "detect/threshold.hpp"
#include "synthetic_tag.hpp"

namespace test_dark_outlines {

using namespace tagbench;

namespace {

// A dark square (side 24 px at (40, 40)) in a light ring 3 px wide on a dark card, the ring cut at the
// middle of its top and bottom sides by dark bridges 3 px wide: the ring falls into two light
// components, so the square's outline is split between two boundary groups (each also holding half
// of the card's inner edge), while the square, the bridges and the card are one dark component.
ImageF broken_ring_image() {
  ImageF img(80, 80, 0.2f);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const double dx = std::abs(x - 40.0), dy = std::abs(y - 40.0), d = std::max(dx, dy);
      if (d <= 12) img.at(x, y) = 0.1f;
      else if (d <= 15 && !(dx <= 1 && dy > 12)) img.at(x, y) = 0.8f;
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

bool finds_square(const std::vector<Quad>& quads) {
  // The black square's corners: pixel centres 28..52, so its edges at 27.5 and 52.5.
  const Corners want = synth::square_tag_corners(40, 40, 25, 0);
  for (const Quad& q : quads)
    if (corner_error(q, want) < 1.0) return true;
  return false;
}

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
  EXPECT_FALSE(DetectorOptions::paper().dark_outlines.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().dark_outlines.enabled);
}

}  // namespace test_dark_outlines
