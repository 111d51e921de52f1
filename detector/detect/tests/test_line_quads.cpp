#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

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

// LineQuadOptions::keep_exact: a family correcting no more bits than spare_bits (16h5 corrects 1;
// spare_bits set to 2 here, the default before session 46) takes its exact readings from the line
// quads; without it, none (the quad decoded but too far for its source). 36h11 (3 - 2 = 1 bit)
// takes its exact reading either way. The threshold stage is made blind (no window has the contrast
// it asks) so that the tag can only come from the line quads.
TEST(LineQuads, ExactReadingsKeptForFamiliesCorrectingFewBits) {
  const Corners c = synth::square_tag_corners(60, 60, 36, 0.3);
  const auto found_by_line_quads = [&](const std::string& family, int id, bool keep_exact) {
    DetectorOptions o;
    o.families = {family};
    o.threshold_quads.threshold.min_contrast = o.threshold_quads.threshold.low_contrast = 0.95f;
    o.threshold_quads.low_contrast.enabled = false;
    o.second_look.enabled = false;
    o.line_quads.keep_exact = keep_exact;
    o.line_quads.spare_bits = 2;
    const TagFamily fam = load_family(family);
    ImageF img = synth::render_tag(120, 120, tag_cells(fam, id), synth::homography_for(c));
    for (float& v : img.data) v = 0.3f + 0.4f * v;  // contrast 0.4, under the threshold stage's floor
    DetectorTrace trace;
    const auto found = Detector(o).detect(img, &trace);
    const bool too_far = std::any_of(trace.quad_outcomes.begin(), trace.quad_outcomes.end(), [&](const QuadOutcome& q) {
      return q.fate == QuadOutcome::Fate::kTooFarForItsSource && q.id == id && q.hamming == 0;
    });
    if (found.size() == 1 && found[0].id == id && found[0].hamming == 0) return std::string("found");
    return std::string(too_far ? "too far" : "not read") + " (" + std::to_string(found.size()) + " found)";
  };
  EXPECT_EQ(found_by_line_quads("16h5", 11, true), "found");
  EXPECT_EQ(found_by_line_quads("16h5", 11, false), "too far (0 found)");
  EXPECT_EQ(found_by_line_quads("36h11", 7, false), "found");
  EXPECT_TRUE(DetectorOptions{}.line_quads.keep_exact);
  EXPECT_TRUE(DetectorOptions::thorough().line_quads.keep_exact);
}

}  // namespace test_line_quads
