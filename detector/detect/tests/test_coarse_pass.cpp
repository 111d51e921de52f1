#include <gtest/gtest.h>

#include <stdexcept>

#include "detect/coarse_pass.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"

namespace test_coarse_pass {

using namespace tagbench;

namespace {

CoarsePassOptions on() {
  CoarsePassOptions o;
  o.enabled = true;
  return o;
}

}  // namespace

// A 36 px dark square 15 grey levels below its ground: under the main pass's 20/255 floor, so the
// full-resolution threshold stage leaves it unknown; the coarse pass (floor 10/255) finds its
// outline, refined on the full-resolution image to within half a pixel.
TEST(CoarsePass, FindsASquareUnderTheMainFloor) {
  const DetectorOptions d;
  const Corners c = synth::square_tag_corners(60, 58, 36, 0.3);
  const ImageF img = synth::filled_quad_image(120, c, 0.60f, 0.60f - 15.0f / 255.0f);
  ThresholdQuadWorkspace ws;
  std::vector<Quad> main;
  find_threshold_quads(img, d.threshold_quads, ws, main);
  EXPECT_GT(synth::best_quad_match(main, c), 3.0);
  EXPECT_LT(synth::best_quad_match(coarse_pass_quads(img, d.threshold_quads, {}, on(), ws), c), 0.5);
  // At the main pass's floor the coarse pass does not see it either.
  CoarsePassOptions same = on();
  same.min_contrast = d.threshold_quads.threshold.min_contrast;
  EXPECT_GT(synth::best_quad_match(coarse_pass_quads(img, d.threshold_quads, {}, same, ws), c), 3.0);
}

// Quads centred inside a tag found already are not returned; min_tag_px drops narrower ones.
TEST(CoarsePass, SkipsCoveredAndNarrowQuads) {
  const DetectorOptions d;
  const Corners c = synth::square_tag_corners(60, 58, 36, 0.3);
  const ImageF img = synth::filled_quad_image(120, c, 0.8f, 0.2f);
  ThresholdQuadWorkspace ws;
  EXPECT_LT(synth::best_quad_match(coarse_pass_quads(img, d.threshold_quads, {}, on(), ws), c), 0.5);
  const std::vector<Corners> covered{synth::square_tag_corners(60, 58, 20, 0)};
  EXPECT_GT(synth::best_quad_match(coarse_pass_quads(img, d.threshold_quads, covered, on(), ws), c), 3.0);
  CoarsePassOptions wide = on();
  wide.min_tag_px = 40;  // wider than the square
  EXPECT_GT(synth::best_quad_match(coarse_pass_quads(img, d.threshold_quads, {}, wide, ws), c), 3.0);
}

// The detector option: on in the thorough profile, off in the default (since session 27) and the
// paper's; validated like every other.
TEST(CoarsePass, OnInTheThoroughProfileOnlyAndValidated) {
  EXPECT_FALSE(DetectorOptions{}.coarse_pass.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().coarse_pass.enabled);
  EXPECT_FALSE(DetectorOptions::paper().coarse_pass.enabled);
  EXPECT_FALSE(CoarsePassOptions{}.enabled);
  DetectorOptions o;
  o.coarse_pass.min_contrast = 1.5f;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.coarse_pass.min_tag_px = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace test_coarse_pass
