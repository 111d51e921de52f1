// The payload reader's ceiling: truth corners decode a clean tag, contrast as the rings give it,
// wrong corners or a flat tag do not decode, and the summary counts what the rows say.
#include <gtest/gtest.h>

#include <cmath>

#include "codes/families.hpp"
#include "realistic/realistic_ceiling.hpp"
#include "clean_camera.hpp"

namespace tagbench::bench {
namespace test_realistic_ceiling {
namespace {

// The tests' quantizing camera, tags 24-32 px with a fixed print and light.
RealisticSettings clean_camera() {
  RealisticSettings s = testing::clean_camera();
  s.black_square_px = {24, 32};
  s.ink_reflectance = {0.05, 0.05};
  s.paper_reflectance = {0.85, 0.85};
  s.face_light = {1, 1};
  return s;
}

ImageF gray_of(const RealisticFrame& f) {
  return to_float_image(ImageU8View{f.image.cols, f.image.rows, static_cast<int>(f.image.step), f.image.data});
}

TEST(RealisticCeiling, TruthCornersOfACleanTagDecodeWithBothReaders) {
  const RealisticSettings s = clean_camera();
  const TagFamily fam = load_family(s.family);
  const RealisticFrame f = make_realistic_frame(s, 0);
  const ImageF gray = gray_of(f);
  ASSERT_FALSE(f.tags.empty());
  for (const RealisticTag& t : f.tags) {
    const TruthReading r = read_at_truth(gray, t, fam, DetectorOptions{});
    EXPECT_TRUE(r.area_decoded);
    EXPECT_TRUE(r.point_decoded);
    EXPECT_TRUE(r.area_soft_decoded);
    EXPECT_EQ(r.area_bits_wrong, 0);
    EXPECT_EQ(r.point_bits_wrong, 0);
    EXPECT_GT(r.contrast_levels, 50);  // ink 0.05, paper 0.85 in full light, gamma-encoded
    EXPECT_LT(r.contrast_levels, 256);
  }
}

TEST(RealisticCeiling, ShiftedCornersOrAFlatImageDoNotDecode) {
  const RealisticSettings s = clean_camera();
  const TagFamily fam = load_family(s.family);
  const RealisticFrame f = make_realistic_frame(s, 1);
  const ImageF gray = gray_of(f);
  RealisticTag t = f.tags.at(0);
  const Eigen::Vector2d shift = (t.corners[1] - t.corners[0]) / 2;  // half the black square sideways
  for (auto& c : t.corners) c += shift;
  const TruthReading shifted = read_at_truth(gray, t, fam, DetectorOptions{});
  EXPECT_FALSE(shifted.area_decoded);
  EXPECT_FALSE(shifted.area_soft_decoded);
  EXPECT_FALSE(shifted.point_decoded);
  const ImageF flat(gray.width, gray.height, 0.5f);
  const TruthReading r = read_at_truth(flat, f.tags.at(0), fam, DetectorOptions{});
  EXPECT_FALSE(r.area_decoded);
  EXPECT_FALSE(r.area_soft_decoded);
  EXPECT_FALSE(r.point_decoded);
  EXPECT_NEAR(r.contrast_levels, 0, 1e-3);
}

TEST(RealisticCeiling, ContrastBands) {
  EXPECT_EQ(contrast_band_of(-3), "<10");
  EXPECT_EQ(contrast_band_of(std::nan("")), "<10");
  EXPECT_EQ(contrast_band_of(10), "10-15");
  EXPECT_EQ(contrast_band_of(19.99), "15-20");
  EXPECT_EQ(contrast_band_of(29), "20-30");
  EXPECT_EQ(contrast_band_of(49), "30-50");
  EXPECT_EQ(contrast_band_of(50), ">=50");
  EXPECT_EQ(contrast_band_names().size(), 6u);
}

TEST(RealisticCeiling, SummaryCountsEachTagOnceAndEachDetectorsDetections) {
  RealisticResult r;
  r.settings.detectors = {"a", "b"};
  RealisticFrameInfo f;
  RealisticTag small, big;
  small.black_square_px = 21;
  big.black_square_px = 35;
  f.tags = {small, big};
  r.frames = {f};
  CeilingResult c;
  TruthReading low, high;
  // low: only the soft decoder reads it, which the default profile's readers (`either`) include
  low.contrast_levels = 12, low.area_decoded = false, low.point_decoded = false, low.area_soft_decoded = true;
  high.contrast_levels = 80, high.area_decoded = true, high.point_decoded = true, high.area_soft_decoded = true;
  c.by_frame = {{low, high}};
  const auto score = [](std::size_t tag, const char* det, bool detected) {
    TagScore s;
    s.tag = tag, s.detector = det, s.detected = detected;
    return s;
  };
  r.scores = {score(0, "a", false), score(0, "b", true), score(1, "a", true), score(1, "b", true)};
  const auto rows = summarize_ceiling(r, c);
  const auto find = [&](const std::string& bin, const std::string& band) {
    for (const auto& row : rows)
      if (row.bin == bin && row.band == band) return row;
    ADD_FAILURE() << bin << " " << band;
    return CeilingSummaryRow{};
  };
  const auto lo = find("20-24", "10-15");
  EXPECT_EQ(lo.tags, 1);
  EXPECT_EQ(lo.area, 0);
  EXPECT_EQ(lo.area_soft, 1);
  EXPECT_EQ(lo.point, 0);
  EXPECT_EQ(lo.either, 1);
  EXPECT_EQ(lo.detected, (std::vector<int>{0, 1}));
  const auto all = find("all", "all");
  EXPECT_EQ(all.tags, 2);
  EXPECT_EQ(all.area, 1);
  EXPECT_EQ(all.area_soft, 2);
  EXPECT_EQ(all.either, 2);
  EXPECT_EQ(all.detected, (std::vector<int>{1, 2}));
  EXPECT_EQ(find("32-40", "all").tags, 1);
  const std::string csv = ceiling_summary_csv(r, rows);
  EXPECT_NE(csv.find("realistic,1,36h11,1,20-24,10-15,1,0,1,0,1,0,1\n"), std::string::npos) << csv;
}

}  // namespace
}  // namespace test_realistic_ceiling
}  // namespace tagbench::bench
