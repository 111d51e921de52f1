// Stage 6: payloads read once per width and decoded against every family; the lowest Hamming
// distance wins, the first family on a tie; the border pre-filter.
#include <gtest/gtest.h>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/decode_quads.hpp"
#include "synthetic_tag.hpp"

namespace test_decode_quads {

using namespace tagbench;

namespace {

const Corners kTruth = synth::square_tag_corners(90, 90, 100, 0.3);

// The quad as quad_search reports a tag printed upright and seen rotated by `r` quarter turns:
// its first corner is the printed corner 4 - r.
Quad quad_of(const Corners& printed, int r) {
  Quad q;
  for (int i = 0; i < 4; ++i)
    q.corners[static_cast<std::size_t>(i)] = printed[static_cast<std::size_t>((i + 4 - r) % 4)];
  q.observed_perimeter = 321;
  return q;
}

// A one-code 16h5-sized family holding `code`.
TagFamily single(const std::string& name, Code code) {
  FamilyInfo info;
  info.name = name;
  info.bits = 16;
  info.min_hamming = 5;
  return TagFamily(info, {code}, false);
}

}  // namespace

TEST(DecodeQuads, DecodesAndOrdersTheCornersFromTheRotation) {
  const TagFamily& f = builtin_family("16h5");
  const ImageF img = synth::render_tag(180, 180, tag_cells(f, 7), synth::homography_for(kTruth));
  for (int r = 0; r < 4; ++r) {
    const std::vector<Quad> quads = {quad_of(kTruth, r)};
    const auto out = decode_quads(img, quads, std::span(&f, 1), 0, PayloadOptions{});
    ASSERT_EQ(out.size(), 1u) << r;
    EXPECT_EQ(out[0].family, "16h5");
    EXPECT_EQ(out[0].id, 7);
    EXPECT_EQ(out[0].hamming, 0);
    EXPECT_EQ(out[0].rotation, r);
    EXPECT_EQ(out[0].corners, kTruth);  // printed order whatever corner the quad started at
    EXPECT_EQ(out[0].observed_perimeter, 321);
    EXPECT_LT((out[0].center - Eigen::Vector2d(90, 90)).norm(), 1e-9);
    EXPECT_GT(out[0].decision_margin, 0.5);
  }
}

TEST(DecodeQuads, LowestHammingWinsThenTheFirstFamily) {
  const Code code = builtin_family("16h5").codes()[4];
  const ImageF img =
      synth::render_tag(180, 180, tag_cells_for_code(code, 4), synth::homography_for(kTruth));
  const std::vector<Quad> quads = {quad_of(kTruth, 0)};
  const auto best_of = [&](std::vector<TagFamily> fams) {
    const auto out = decode_quads(img, quads, fams, 2, PayloadOptions{});
    return out.size() == 1 ? out[0].family + "/" + std::to_string(out[0].hamming) : std::string("none");
  };
  const TagFamily exact_a = single("a", code), exact_b = single("b", code), off_by_one = single("c", code ^ 0x100);
  // Equal Hamming distance: the first family in the given order.
  EXPECT_EQ(best_of({exact_a, exact_b}), "a/0");
  EXPECT_EQ(best_of({exact_b, exact_a}), "b/0");
  // A lower Hamming distance wins whatever the order.
  EXPECT_EQ(best_of({off_by_one, exact_b}), "b/0");
  EXPECT_EQ(best_of({exact_b, off_by_one}), "b/0");
  EXPECT_EQ(best_of({off_by_one}), "c/1");
}

TEST(DecodeQuads, OneReadingPerPayloadWidth) {
  const TagFamily& f = builtin_family("16h5");
  const ImageF img = synth::render_tag(180, 180, tag_cells(f, 2), synth::homography_for(kTruth));
  const std::vector<Quad> quads = {quad_of(kTruth, 1), quad_of(kTruth, 2)};
  // Two families of width 4, one of width 6: two readings per quad, not three.
  const std::vector<TagFamily> fams = {builtin_family("36h11"), f, single("x", f.codes()[0])};
  std::vector<PayloadReading> readings;
  const auto out = decode_quads(img, quads, fams, 0, PayloadOptions{}, nullptr, &readings);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].rotation, 1);
  EXPECT_EQ(out[1].rotation, 2);
  ASSERT_EQ(readings.size(), 4u);
  EXPECT_EQ(readings[0].payload_points.size(), 16u);  // d = 4 first (widths in increasing order)
  EXPECT_EQ(readings[1].payload_points.size(), 36u);
  EXPECT_FALSE(readings[0].white_points.empty());
  // Without the readings vector the points are not kept and the detections are the same.
  const auto again = decode_quads(img, quads, fams, 0, PayloadOptions{});
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[1].corners, out[1].corners);
}

TEST(DecodeQuads, QuickRejectAppliesTheBorderPreFilter) {
  const TagFamily& f = builtin_family("16h5");
  ImageF img = synth::render_tag(180, 180, tag_cells(f, 11), synth::homography_for(kTruth));
  // Grey blobs over the middles of two sides' rings: the 8-sample border test fails there, while
  // the full border models (every ring cell) still read the payload.
  for (const auto& [a, b] : {std::pair{kTruth[0], kTruth[1]}, std::pair{kTruth[2], kTruth[3]}}) {
    const Eigen::Vector2d m = 0.5 * (a + b);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if ((Eigen::Vector2d(x, y) - m).norm() < 12) img.at(x, y) = 0.5f;
  }
  const std::vector<Quad> quads = {quad_of(kTruth, 0)};
  ASSERT_FALSE(border_contrast_plausible(img, quads[0].corners, 4, PayloadOptions{}.min_contrast));
  PayloadOptions off;
  off.quick_reject = false;
  std::vector<PayloadReading> readings;
  const auto read = decode_quads(img, quads, std::span(&f, 1), 2, off, nullptr, &readings);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].id, 11);
  readings.clear();
  EXPECT_TRUE(decode_quads(img, quads, std::span(&f, 1), 2, PayloadOptions{}, nullptr, &readings).empty());
  EXPECT_TRUE(readings.empty());  // rejected before anything was read
}

// The check with slack admits a quad placed 0.6 of a ring cell outside the black square (as an inner
// square inherits its printed square's error), which the plain check refuses; not one 1.5 x too large,
// nor one on a flat image, nor one whose side leaves the image.
TEST(DecodeQuads, BorderCheckWithSlackAdmitsAQuadAFractionOfACellOff) {
  const TagFamily& f = builtin_family("16h5");  // d = 4: a ring cell is a third of the half-width
  const ImageF img = synth::render_tag(180, 180, tag_cells(f, 11), synth::homography_for(kTruth));
  const auto scaled = [](double k) {
    Corners c = kTruth;
    const Eigen::Vector2d centre(90, 90);
    for (auto& p : c) p = centre + k * (p - centre);
    return c;
  };
  const double contrast = PayloadOptions{}.min_contrast;
  EXPECT_TRUE(border_contrast_plausible(img, kTruth, 4, contrast));
  EXPECT_TRUE(border_contrast_plausible_with_slack(img, kTruth, 4, contrast, 4));
  const Corners off = scaled(1.2);  // each side 10 px (0.6 cell) outward
  EXPECT_FALSE(border_contrast_plausible(img, off, 4, contrast));
  EXPECT_TRUE(border_contrast_plausible_with_slack(img, off, 4, contrast, 4));
  EXPECT_FALSE(border_contrast_plausible_with_slack(img, scaled(1.5), 4, contrast, 1));
  ImageF flat = img;
  for (float& v : flat.data) v = 0.5f;
  EXPECT_FALSE(border_contrast_plausible_with_slack(flat, kTruth, 4, contrast, 1));
  // A tag whose black square ends 10 px from the left edge: the plain check's samples (half a cell
  // out) stay inside, the outermost slack samples (0.75 and 1 cell out) do not, and that side fails;
  // the same tag further in passes on all four sides.
  const Corners near_edge = synth::square_tag_corners(60, 90, 100, 0);
  const ImageF edge_img = synth::render_tag(180, 180, tag_cells(f, 11), synth::homography_for(near_edge));
  EXPECT_TRUE(border_contrast_plausible(edge_img, near_edge, 4, contrast));
  EXPECT_FALSE(border_contrast_plausible_with_slack(edge_img, near_edge, 4, contrast, 4));
  EXPECT_TRUE(border_contrast_plausible_with_slack(edge_img, near_edge, 4, contrast, 3));
  const Corners inside = synth::square_tag_corners(90, 90, 100, 0);
  const ImageF inside_img = synth::render_tag(180, 180, tag_cells(f, 11), synth::homography_for(inside));
  EXPECT_TRUE(border_contrast_plausible_with_slack(inside_img, inside, 4, contrast, 4));
}

// hamming_by_family: each family corrects at most min(max_hamming, (h - 1) / 3) bits, so one max_hamming
// of 3 lets a 36h11 tag (h = 11) with 3 bits flipped through but not a 16h5 tag (h = 5) with 2 flipped.
TEST(DecodeQuads, BitsCorrectedByFamilyFollowTheFamilysDistance) {
  const auto decoded = [](const TagFamily& f, Code flips, int max_hamming, bool by_family) {
    const Code printed = f.codes()[3] ^ flips;
    const ImageF img = synth::render_tag(180, 180, tag_cells_for_code(printed, f.payload_width()),
                                         synth::homography_for(kTruth));
    const std::vector<Quad> quads = {quad_of(kTruth, 0)};
    const auto out = decode_quads(img, quads, std::span(&f, 1), max_hamming, PayloadOptions{}, nullptr, nullptr,
                                  nullptr, by_family);
    return out.size() == 1 && out[0].id == 3 ? out[0].hamming : -1;
  };
  const TagFamily &f36 = builtin_family("36h11"), &f16 = builtin_family("16h5");
  EXPECT_EQ(decoded(f36, 0x111, 3, true), 3);   // (11 - 1) / 3 = 3
  EXPECT_EQ(decoded(f36, 0x111, 2, true), -1);  // max_hamming still caps it
  EXPECT_EQ(decoded(f36, 0x1111, 3, true), -1);
  EXPECT_EQ(decoded(f16, 0x1, 3, true), 1);     // (5 - 1) / 3 = 1
  EXPECT_EQ(decoded(f16, 0x11, 3, true), -1);
  EXPECT_EQ(decoded(f16, 0x11, 3, false), 2);   // off: max_hamming for every family
  DetectorOptions o;
  EXPECT_EQ(o.bits_corrected(f36.min_hamming()), 3);
  EXPECT_EQ(o.bits_corrected(builtin_family("25h9").min_hamming()), 2);
  EXPECT_EQ(o.bits_corrected(f16.min_hamming()), 1);
  EXPECT_EQ(DetectorOptions::paper().bits_corrected(f36.min_hamming()), 1);
}

}  // namespace test_decode_quads
