#include <gtest/gtest.h>

#include <stdexcept>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/line_quads.hpp"
#include "synthetic_tag.hpp"

namespace test_line_quads {

using namespace tagbench;

namespace {

LineQuadOptions on(double max_side_px = 64) {
  LineQuadOptions o;
  o.enabled = true;
  o.max_side_px = max_side_px;
  return o;
}

}  // namespace

// A small dark square and a small light one each give a quad on their outline, clockwise on screen
// like every quad, and observed_perimeter 0.
TEST(LineQuads, DarkAndLightSquaresGiveTheirOutline) {
  LineQuadScratch s;
  for (const bool dark : {true, false}) {
    const Corners c = synth::square_tag_corners(40, 40, 22, 0.4);
    const ImageF img = synth::filled_quad_image(80, c, dark ? 0.8f : 0.2f, dark ? 0.2f : 0.75f);
    const auto quads = line_quads(img, {}, on(), s);
    EXPECT_LT(synth::best_quad_match(quads, c), 1.0) << (dark ? "dark" : "light");
    for (const Quad& q : quads) EXPECT_EQ(q.observed_perimeter, 0);
  }
}

// Edges found on a resampled image (scale < 1) are mapped back: the outline is still within a pixel
// or two of a 30 px square's corners at 0.6 and 0.5.
TEST(LineQuads, EdgesFromAResampledImageMapBack) {
  LineQuadScratch s;
  const Corners c = synth::square_tag_corners(50, 46, 30, 0.4);
  const ImageF img = synth::filled_quad_image(100, c, 0.8f, 0.2f);
  for (const double scale : {0.6, 0.5}) {
    LineQuadOptions o = on();
    o.scale = scale;
    EXPECT_LT(synth::best_quad_match(line_quads(img, {}, o, s), c), 1.5) << scale;
  }
}

// Quads centred inside a found tag, and quads with a side over max_side_px, are not returned.
TEST(LineQuads, SkipsCoveredAndLargeQuads) {
  LineQuadScratch s;
  const Corners c = synth::square_tag_corners(40, 40, 22, 0.4);
  const ImageF img = synth::filled_quad_image(80, c, 0.8f, 0.2f);
  const std::vector<Corners> covered{synth::square_tag_corners(40, 40, 30, 0)};
  EXPECT_GT(synth::best_quad_match(line_quads(img, covered, on(), s), c), 5.0);
  EXPECT_GT(synth::best_quad_match(line_quads(img, {}, on(20), s), c), 5.0);
  EXPECT_LT(synth::best_quad_match(line_quads(img, {}, on(24), s), c), 1.0);
}

// The detector option: on in the default profile (half-size edges, not at half resolution) and the
// thorough one, off in the paper's; validated like every other.
TEST(LineQuads, OnInTheDefaultAndThoroughProfilesAndValidated) {
  EXPECT_TRUE(DetectorOptions{}.line_quads.enabled);
  EXPECT_FALSE(DetectorOptions{}.line_quads.at_half_resolution);
  EXPECT_FALSE(DetectorOptions::paper().line_quads.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().line_quads.enabled);
  DetectorOptions o;
  o.line_quads.max_side_px = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.line_quads.segments.min_density = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.line_quads.segments.angle_tolerance_deg = 120;  // p = tau / 180 must stay under 1/2 for LSD's test
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.line_quads.segments.min_gradient = 0;  // the unit gradient would divide by a zero magnitude
  EXPECT_THROW(o.validate(), std::invalid_argument);
  for (const double scale : {0.0, 1.5}) {
    o = DetectorOptions{};
    o.line_quads.scale = scale;
    EXPECT_THROW(o.validate(), std::invalid_argument) << scale;
  }
  o = DetectorOptions{};
  o.line_quads.segments.straight_sides = 3;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// With the option on, a detector still finds a plain tag once (no duplicate from the line quads).
TEST(LineQuads, DetectorWithLineQuadsReportsAPlainTagOnce) {
  DetectorOptions o;
  o.line_quads.enabled = true;
  const Detector det(o);
  const Corners c = synth::square_tag_corners(60, 60, 40, 0.3);
  const TagFamily fam = load_family("36h11");
  const ImageF img = synth::render_tag(120, 120, tag_cells(fam, 7), synth::homography_for(c));
  const auto found = det.detect(img);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 7);
}

// LineQuadOptions::at_half_resolution: off (the default profile's), a half-resolution run reads no
// line quad, so it reads the quads of the same run without them; on, it reads more (the outline of a
// plain dark square beside the tag, which no tag covers).
TEST(LineQuads, AtHalfResolutionOnlyWhenAsked) {
  const Corners c = synth::square_tag_corners(60, 60, 40, 0.3);
  const TagFamily fam = load_family("36h11");
  ImageF img = synth::render_tag(200, 120, tag_cells(fam, 7), synth::homography_for(c));
  for (int y = 45; y < 75; ++y)
    for (int x = 135; x < 165; ++x) img.at(x, y) = 0.15f;
  const auto reads = [&](const DetectorOptions& o) {
    DetectorTrace trace;
    const auto found = Detector(o).detect(img, &trace);
    EXPECT_EQ(found.size(), 1u);
    return trace.quad_outcomes.size();
  };
  DetectorOptions o;
  o.half_resolution = true;
  ASSERT_FALSE(o.line_quads.at_half_resolution);
  DetectorOptions none = o;
  none.line_quads.enabled = false;
  DetectorOptions asked = o;
  asked.line_quads.at_half_resolution = true;
  EXPECT_EQ(reads(o), reads(none));
  EXPECT_GT(reads(asked), reads(o));
}

}  // namespace test_line_quads
