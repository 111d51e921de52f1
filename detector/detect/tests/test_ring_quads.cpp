#include <gtest/gtest.h>

#include <stdexcept>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/detector.hpp"
#include "detect/printed_square.hpp"
#include "detect/ring_quads.hpp"
#include "detect/threshold.hpp"
#include "synthetic_tag.hpp"

namespace test_ring_quads {

using namespace tagbench;

namespace {

// A light square ring (outer side `outer`, `width` px wide) at (cx, cy) on a dark ground, with a dark
// filling: the printed square's white ring on a darker card.
ImageF ring_image(int size, double cx, double cy, double outer, double width, float ground, float ring, float inside) {
  ImageF img(size, size, ground);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double dx = std::abs(x - cx), dy = std::abs(y - cy), d = std::max(dx, dy);
      if (d <= outer / 2) img.at(x, y) = d > outer / 2 - width ? ring : inside;
    }
  return img;
}

using Pass = synth::ThresholdPass;

}  // namespace

// The ring's outline against the ground is a light-inside group: one quad, the ring's outer square.
TEST(RingQuads, FitsTheRingsOuterSquare) {
  const ImageF img = ring_image(80, 40, 40, 30, 3, 0.2f, 0.8f, 0.25f);
  Pass p(img);
  QuadFitScratch s;
  const auto quads = ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true}, s);
  ASSERT_FALSE(quads.empty());
  bool outer = false;
  for (const Quad& q : quads) {
    double worst = 0;
    const Corners want = synth::square_tag_corners(40, 40, 30, 0);
    for (const auto& c : q.corners) {
      double best = 1e9;
      for (const auto& w : want) best = std::min(best, (c - w).norm());
      worst = std::max(worst, best);
    }
    outer = outer || worst < 1.0;
  }
  EXPECT_TRUE(outer);
  // Off, a box outside [min, max], or a light component over max_fill of the box: nothing. (The
  // ring's light pixels are about 4 x 30 x 3 = 360 of the box's 900.)
  EXPECT_TRUE(ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{}, s).empty());
  EXPECT_TRUE(ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true, .max_size_px = 25}, s).empty());
  EXPECT_TRUE(ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true, .min_size_px = 35}, s).empty());
  EXPECT_TRUE(ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true, .max_fill = 0.3}, s).empty());
  EXPECT_FALSE(ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true, .max_fill = 0.5}, s).empty());
  // A light square with nothing dark inside has no inner edge: refused by min_hole (its flat middle is
  // unknown to the threshold, so its light component is only a band and passes max_fill).
  const ImageF filled = ring_image(80, 40, 40, 30, 3, 0.2f, 0.8f, 0.8f);
  Pass f(filled);
  EXPECT_FALSE(ring_quads(f.groups, f.comp, filled, QuadFitOptions{}, RingQuadOptions{.enabled = true, .min_hole = 0}, s).empty());
  EXPECT_TRUE(ring_quads(f.groups, f.comp, filled, QuadFitOptions{}, RingQuadOptions{.enabled = true}, s).empty());
  const ImageF other(81, 80, 0.5f);  // components of another image's size
  EXPECT_THROW(ring_quads(p.groups, p.comp, other, QuadFitOptions{}, RingQuadOptions{.enabled = true}, s), std::invalid_argument);
}

// A tag on a dark card: its white ring gives a ring quad whose printed-square reading is the black
// square (the detector's path: ring_quads, then black_squares_in_printed_squares), and the detector
// with ring_quads on reports the tag there.
TEST(RingQuads, ARingsInnerSquareIsTheTag) {
  const TagFamily fam = load_family("36h11");
  const Corners truth = synth::square_tag_corners(48, 48, 24, 0.3);
  const ImageF img = synth::render_tag(96, 96, tag_cells(fam, 5), synth::homography_for(truth), 0.2f, 8, 0.05f, 0.9f);
  Pass p(img);
  QuadFitScratch s;
  const auto rings = ring_quads(p.groups, p.comp, img, QuadFitOptions{}, RingQuadOptions{.enabled = true}, s);
  const auto inner = black_squares_in_printed_squares(rings, std::vector<bool>(rings.size(), true), std::vector<int>{6});
  double best = 1e9;
  for (const Quad& q : inner)
    for (int r = 0; r < 4; ++r) {  // any cyclic order of the corners
      Corners c;
      for (int k = 0; k < 4; ++k) c[static_cast<std::size_t>(k)] = q.corners[static_cast<std::size_t>((k + r) % 4)];
      best = std::min(best, synth::corner_rms(c, truth));
    }
  EXPECT_LT(best, 1.0);
  DetectorOptions opt;
  const auto found = Detector(opt).detect(img);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 5);
  EXPECT_LT(synth::corner_rms(found[0].corners, truth), 0.5);
  EXPECT_FALSE(DetectorOptions::paper().ring_quads.enabled);
  EXPECT_TRUE(DetectorOptions().ring_quads.enabled);
}

}  // namespace test_ring_quads
