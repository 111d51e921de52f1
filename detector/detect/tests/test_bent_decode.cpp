#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/bent_decode.hpp"
#include "detect/blur.hpp"
#include "detect/decode_quads.hpp"
#include "detect/detector.hpp"
#include "synthetic_folded.hpp"
#include "synthetic_tag.hpp"

namespace test_bent_decode {

using namespace tagbench;

namespace {

// The fold line shifted 6 px along itself and 6 px sideways, as a fold seen obliquely looks.
synth::FoldedTag folded() { return synth::folded_square(70.4, 70.2, 64, 6, -6, 6); }

ImageF folded_image(int id) {
  return gaussian_blur(synth::render_folded(140, 140, tag_cells(builtin_family("36h11"), id), folded()), 0.6);
}

std::vector<Quad> fitted_quads() {
  Quad q;
  q.corners = synth::fitted_quad(folded());
  return {q};
}

// The first 36h11 id whose folded tag the flat reading (the default profile's area reader) reads but
// does not decode, or -1. Most ids read through even so: one bit is corrected and only the cells near
// the fold's ends move by much.
int misread_id() {
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  const PayloadAreaOptions area;
  for (int id = 0; id < 60; ++id) {
    std::vector<QuadOutcome> outcomes;
    if (decode_quads(folded_image(id), fitted_quads(), fams, 1, PayloadOptions{}, &area, nullptr, &outcomes).empty() &&
        outcomes[0].fate == QuadOutcome::Fate::kNotDecoded)
      return id;
  }
  return -1;
}

std::vector<std::uint8_t> to_u8(const ImageF& img) {
  std::vector<std::uint8_t> out(img.data.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<std::uint8_t>(std::lround(255 * img.data[i]));
  return out;
}

}  // namespace

// A folded 36h11 tag whose flat reading fails is decoded by the second chance, with the right id,
// corners near the black square's and the quad's outcome updated; with the option off, nothing.
TEST(BentDecode, FoldedTagMisreadFlatIsDecoded) {
  const int id = misread_id();
  ASSERT_GE(id, 0);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  const ImageF img = folded_image(id);
  std::vector<QuadOutcome> outcomes(1);
  outcomes[0].fate = QuadOutcome::Fate::kNotDecoded;
  const auto found = decode_bent_quads(img, img, fitted_quads(), outcomes, fams, 1, false, PayloadAreaOptions{}, 0.02,
                                       BentReadOptions{});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, id);
  EXPECT_EQ(found[0].hamming, 0);
  // The re-located corners: near the true ones (in printed order, whatever the rotation).
  double best = INFINITY;
  for (int r = 0; r < 4; ++r) {
    Corners c;
    for (int i = 0; i < 4; ++i) c[static_cast<std::size_t>(i)] = folded().corners[static_cast<std::size_t>((i + r) % 4)];
    best = std::min(best, synth::corner_rms(found[0].corners, c));
  }
  EXPECT_LT(best, 0.5);
  EXPECT_EQ(outcomes[0].fate, QuadOutcome::Fate::kDecoded);
  EXPECT_EQ(outcomes[0].id, id);
  BentReadOptions off;
  off.enabled = false;
  outcomes[0].fate = QuadOutcome::Fate::kNotDecoded;
  EXPECT_TRUE(decode_bent_quads(img, img, fitted_quads(), outcomes, fams, 1, false, PayloadAreaOptions{}, 0.02, off).empty());
  // A quad whose shortest side is under min_side_px is not re-read.
  BentReadOptions small_only;
  small_only.min_side_px = 1000;
  EXPECT_TRUE(
      decode_bent_quads(img, img, fitted_quads(), outcomes, fams, 1, false, PayloadAreaOptions{}, 0.02, small_only).empty());
}

// Only kNotDecoded quads with a bent side are re-read: a flat tag's quad marked kNotDecoded stays
// undecoded, and so does a folded one whose outcome says it was not read.
TEST(BentDecode, StraightSidesOrOtherOutcomesAreLeftAlone) {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  const Corners c = synth::square_tag_corners(70, 70, 64, 0.2);
  const ImageF flat = gaussian_blur(synth::render_tag(140, 140, tag_cells(f, 4), synth::homography_for(c)), 0.6);
  Quad q;
  q.corners = c;
  std::vector<QuadOutcome> outcomes(1);
  outcomes[0].fate = QuadOutcome::Fate::kNotDecoded;
  EXPECT_TRUE(
      decode_bent_quads(flat, flat, std::vector<Quad>{q}, outcomes, fams, 1, false, PayloadAreaOptions{}, 0.02, BentReadOptions{})
          .empty());
  const int id = misread_id();
  ASSERT_GE(id, 0);
  const ImageF bent = folded_image(id);
  outcomes[0].fate = QuadOutcome::Fate::kBorderRejected;
  EXPECT_TRUE(
      decode_bent_quads(bent, bent, fitted_quads(), outcomes, fams, 1, false, PayloadAreaOptions{}, 0.02, BentReadOptions{})
          .empty());
}

// The whole detector: the default profile finds the folded tag; with DetectorOptions::bent off it
// finds it only if its own quad happens to read it flat.
TEST(BentDecode, DetectorFindsTheFoldedTag) {
  const int id = misread_id();
  ASSERT_GE(id, 0);
  const auto px = to_u8(folded_image(id));
  const ImageU8View view{140, 140, 140, px.data()};
  const auto on = Detector(DetectorOptions{}).detect(view);
  ASSERT_EQ(on.size(), 1u);
  EXPECT_EQ(on[0].id, id);
  DetectorOptions o;
  o.bent.enabled = false;
  const auto off = Detector(o).detect(view);
  EXPECT_TRUE(off.empty() || off[0].id == id);
}

}  // namespace test_bent_decode
