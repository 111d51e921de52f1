#include <gtest/gtest.h>

#include <cmath>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/border_kink.hpp"
#include "synthetic_folded.hpp"
#include "synthetic_tag.hpp"

using namespace tagbench;

// A flat tag's sides are straight: every kink is a small fraction of a pixel, the blur about the
// rendering's (an 8x8-supersampled box, then a Gaussian of 0.6 px).
TEST(BorderKink, FlatTagSidesAreStraight) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = synth::square_tag_corners(60.3, 58.7, 64, 0.3);
  const ImageF img = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, 5), synth::homography_for(c)), 0.6);
  const auto s = measure_border_kinks(img, c);
  ASSERT_TRUE(s.has_value());
  for (const SideKink& k : *s) {
    EXPECT_TRUE(k.valid);
    EXPECT_LT(std::abs(k.kink_px), 0.15);
  }
  EXPECT_LT(max_kink_px(*s), 0.15);
  EXPECT_NEAR(median_blur_px(*s), 0.65, 0.2);
}

// A heavier blur is measured as such (sigma 2 px on top of the rendering's own).
TEST(BorderKink, BlurIsMeasured) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = synth::square_tag_corners(60, 60, 64, 0.1);
  const ImageF img = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, 9), synth::homography_for(c)), 2.0);
  const auto s = measure_border_kinks(img, c);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(median_blur_px(*s), 2.0, 0.3);
}

// A tag folded along its vertical centre line, the fold points 2 px outside the straight sides: the
// top and bottom sides show the kink (2 px from the chord of their ends) at their middles, the left
// and right sides stay straight; the fold points are found within a few tenths of a pixel.
TEST(BorderKink, FoldedTagShowsItsKinkAndFold) {
  const TagFamily& f = builtin_family("36h11");
  const synth::FoldedTag t = synth::folded_square(60.4, 60.2, 64, 2.0, 2.0);
  const ImageF img = gaussian_blur(synth::render_folded(120, 120, tag_cells(f, 3), t), 0.6);
  // The quad a line fit would give: straight sides through the bent ones' average (here: the ends).
  const auto s = measure_border_kinks(img, t.corners);
  ASSERT_TRUE(s.has_value());
  for (const SideKink& k : *s) ASSERT_TRUE(k.valid);
  EXPECT_NEAR(std::abs((*s)[0].kink_px), 2.0, 0.3);
  EXPECT_NEAR(std::abs((*s)[2].kink_px), 2.0, 0.3);
  EXPECT_LT(std::abs((*s)[1].kink_px), 0.2);
  EXPECT_LT(std::abs((*s)[3].kink_px), 0.2);
  EXPECT_LT(((*s)[0].fold_point - t.fold_top).norm(), 0.4);
  EXPECT_LT(((*s)[2].fold_point - t.fold_bottom).norm(), 0.4);
  EXPECT_GT(max_kink_significance(*s), 10);
}

// Corners that give no homography, or an empty image: no measurement.
TEST(BorderKink, DegenerateInputGivesNothing) {
  const ImageF img(40, 40);
  const Corners line = {Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 3), Eigen::Vector2d(4, 4)};
  EXPECT_FALSE(measure_border_kinks(img, line).has_value());
  EXPECT_FALSE(measure_border_kinks(ImageF(), synth::square_tag_corners(20, 20, 10, 0)).has_value());
}
