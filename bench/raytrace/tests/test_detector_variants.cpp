// The experiments' detector variants (detector_variants.hpp): each key sets its option, pairs apply in
// order, and a bad pair is refused with the detector's name and the pair.
#include "raytrace/detector_variants.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace tagbench::bench {
namespace test_detector_variants {
namespace {

std::string refusal(const std::string& spec) {
  DetectorOptions o;
  try {
    apply_detector_variant(o, spec, "tagbench/" + spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DetectorVariants, AnEmptySpecLeavesTheOptionsAsTheyAre) {
  DetectorOptions o;
  apply_detector_variant(o, "", "tagbench");
  EXPECT_EQ(o.threshold_quads.threshold.min_contrast, DetectorOptions{}.threshold_quads.threshold.min_contrast);
  EXPECT_EQ(o.second_look.enabled, DetectorOptions{}.second_look.enabled);
}

TEST(DetectorVariants, EachPairSetsItsOptionInOrder) {
  DetectorOptions o;
  apply_detector_variant(o, "contrast=0.04/look=0/finder=gradient/reader=point/hamming=1/contrast=0.06", "x");
  EXPECT_FLOAT_EQ(o.threshold_quads.threshold.min_contrast, 0.06f);  // the later pair wins
  EXPECT_FALSE(o.second_look.enabled);
  EXPECT_EQ(o.quad_finder, QuadFinderKind::kGradient);
  EXPECT_EQ(o.payload_reader, PayloadReaderKind::kPoint);
  EXPECT_EQ(o.max_hamming, 1);
  EXPECT_FALSE(o.hamming_by_family);
  apply_detector_variant(o, "look=1/look_max=30/look_min=0/posechoice_lens=0", "x");
  EXPECT_TRUE(o.second_look.enabled);
  EXPECT_DOUBLE_EQ(o.second_look.max_size_px, 30);
  EXPECT_DOUBLE_EQ(o.second_look.min_size_px, 0);
  EXPECT_FALSE(o.pose_choice.with_lens);
  apply_detector_variant(o, "dfr_radii=0:0.75:1.25", "x");
  EXPECT_EQ(o.defocus_read.radii_cells, (std::vector<double>{0, 0.75, 1.25}));
  apply_detector_variant(o, "cc=1/cc_max=48/cc_rej=1/cc_spare=0/cc_support=0.9", "x");
  EXPECT_TRUE(o.corner_completion.enabled);
  EXPECT_DOUBLE_EQ(o.corner_completion.max_side_px, 48);
  EXPECT_TRUE(o.corner_completion.border_rejected);
  EXPECT_EQ(o.corner_completion.spare_bits, 0);
  EXPECT_DOUBLE_EQ(o.corner_completion.min_support, 0.9);
}

TEST(DetectorVariants, BadPairsAreRefusedNamingTheDetectorAndThePair) {
  EXPECT_EQ(refusal("nosuchkey=1"), "detector 'tagbench/nosuchkey=1': unknown variant key 'nosuchkey'");
  EXPECT_EQ(refusal("contrast"), "detector 'tagbench/contrast': 'contrast' is not KEY=VALUE");
  EXPECT_EQ(refusal("contrast=abc"), "detector 'tagbench/contrast=abc': contrast='abc' is not a number");
  EXPECT_EQ(refusal("contrast="), "detector 'tagbench/contrast=': contrast='' is not a number");
  EXPECT_EQ(refusal("look=1x"), "detector 'tagbench/look=1x': look='1x' is not a number");
  EXPECT_EQ(refusal("contrast=nan"), "detector 'tagbench/contrast=nan': contrast='nan' is not a number");
  EXPECT_EQ(refusal("finder=fast"), "detector 'tagbench/finder=fast': finder='fast' is not gradient or threshold");
  EXPECT_EQ(refusal("dfr_radii=0::1"), "detector 'tagbench/dfr_radii=0::1': dfr_radii='0::1' is not a colon-separated list of numbers");
  EXPECT_EQ(refusal("dfr_radii=0:x"), "detector 'tagbench/dfr_radii=0:x': dfr_radii='0:x' is not a colon-separated list of numbers");
  EXPECT_EQ(refusal("reader=pixel"), "detector 'tagbench/reader=pixel': reader='pixel' is not point or area");
}

}  // namespace
}  // namespace test_detector_variants
}  // namespace tagbench::bench
