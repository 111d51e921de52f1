#include <gtest/gtest.h>

#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/corner_completion.hpp"
#include "detect/decode_quads.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"

namespace test_corner_completion {

using namespace tagbench;

namespace {

constexpr int kId = 42;

// A 28 px 36h11 tag, turned and slightly blurred (a parallelogram: the square seen face-on).
Corners truth() { return synth::square_tag_corners(40.2, 39.7, 28, 0.3); }

ImageF tag_image() {
  return gaussian_blur(synth::render_tag(80, 80, tag_cells(builtin_family("36h11"), kId), synth::homography_for(truth())),
                       0.7);
}

// The truth with corner k cut short: moved 40 % of the way toward the opposite corner (the quad a
// shadow's edge across that corner would leave).
Corners cut(int k) {
  Corners c = truth();
  const auto i = static_cast<std::size_t>(k), o = static_cast<std::size_t>((k + 2) & 3);
  c[i] += 0.4 * (c[o] - c[i]);
  return c;
}

QuadOutcome outcome(QuadOutcome::Fate fate) {
  QuadOutcome o;
  o.fate = fate;
  return o;
}

double max_error(const Corners& a, const Corners& b) {
  double e = 0;
  for (std::size_t i = 0; i < 4; ++i) e = std::max(e, (a[i] - b[i]).norm());
  return e;
}

CornerCompletionOptions on() {
  CornerCompletionOptions o;
  o.enabled = true;
  return o;
}

}  // namespace

TEST(CornerCompletion, TheOtherThreeCornersPredictTheFourthOfAParallelogram) {
  const Corners t = truth();
  for (int k = 0; k < 4; ++k) EXPECT_LT(max_error(complete_corner(t, k), t), 1e-9) << k;
  const Corners c = cut(2);
  EXPECT_LT(max_error(complete_corner(c, 2), t), 1e-9);  // the cut corner restored
  EXPECT_GT(max_error(complete_corner(c, 0), t), 5.0);   // a good corner replaced: wrong
}

TEST(CornerCompletion, TheRestoredCornerHasTheBorderBehindItAndAWrongOneHasNot) {
  const ImageF img = tag_image();
  const CornerCompletionOptions opt = on();
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(completion_supported(img, 6, complete_corner(cut(k), k), k, opt)) << k;
    // Completing a good corner of the cut quad moves it off the tag: no border along its sides.
    const int other = (k + 2) & 3;
    EXPECT_FALSE(completion_supported(img, 6, complete_corner(cut(k), other), other, opt)) << k;
  }
  // A flat image supports nothing.
  const ImageF flat(80, 80, 0.5f);
  EXPECT_FALSE(completion_supported(flat, 6, truth(), 0, opt));
}

TEST(CornerCompletion, CompletesOnlyUndecodedQuadsOfTheSizeAskedThatNoTagCovers) {
  const ImageF img = tag_image();
  Quad q;
  q.corners = cut(1);
  const std::vector<Quad> quads{q};
  const std::vector<QuadOutcome> read{outcome(QuadOutcome::Fate::kNotDecoded)};
  const CornerCompletionOptions opt = on();

  const std::vector<Quad> got = completed_quads(img, 6, quads, read, {}, opt);
  ASSERT_FALSE(got.empty());
  bool restored = false;
  for (const Quad& c : got) {
    restored = restored || max_error(c.corners, truth()) < 1e-6;
    EXPECT_EQ(c.observed_perimeter, 0);
    EXPECT_EQ(c.segments[0], -1);
  }
  EXPECT_TRUE(restored);

  // Off; a decoded or border-rejected quad; sizes outside the bounds; a tag already covering it; a
  // size mismatch: nothing.
  CornerCompletionOptions off = opt;
  off.enabled = false;
  EXPECT_TRUE(completed_quads(img, 6, quads, read, {}, off).empty());
  for (const auto fate : {QuadOutcome::Fate::kDecoded, QuadOutcome::Fate::kBorderRejected, QuadOutcome::Fate::kUnreadable})
    EXPECT_TRUE(completed_quads(img, 6, quads, std::vector<QuadOutcome>{outcome(fate)}, {}, opt).empty());
  CornerCompletionOptions small = opt;
  small.max_side_px = 20;
  EXPECT_TRUE(completed_quads(img, 6, quads, read, {}, small).empty());
  CornerCompletionOptions large = opt;
  large.min_side_px = 40;
  EXPECT_TRUE(completed_quads(img, 6, quads, read, {}, large).empty());
  const std::vector<Corners> covered{truth()};
  EXPECT_TRUE(completed_quads(img, 6, quads, read, covered, opt).empty());
  EXPECT_TRUE(completed_quads(img, 6, quads, {}, {}, opt).empty());

  // The border-rejected ones too when asked.
  CornerCompletionOptions rejected = opt;
  rejected.border_rejected = true;
  EXPECT_FALSE(
      completed_quads(img, 6, quads, std::vector<QuadOutcome>{outcome(QuadOutcome::Fate::kBorderRejected)}, {}, rejected)
          .empty());

  // A parallelogram already (the truth): no completion moves a corner by min_move_px.
  Quad whole;
  whole.corners = truth();
  EXPECT_TRUE(completed_quads(img, 6, std::vector<Quad>{whole}, read, {}, opt).empty());
}

TEST(CornerCompletion, ACutQuadIsMisreadAndItsCompletionReadsTheTag) {
  const ImageF img = tag_image();
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  PayloadAreaOptions area;
  area.min_contrast = PayloadOptions{}.min_contrast;
  int completed_and_read = 0;
  for (int k = 0; k < 4; ++k) {
    Quad q;
    q.corners = cut(k);
    std::vector<QuadOutcome> outcomes;
    const auto first = decode_quads(img, std::vector<Quad>{q}, fams, 3, PayloadOptions{}, &area, nullptr, &outcomes, true);
    EXPECT_TRUE(first.empty()) << k;
    if (outcomes.empty() || outcomes[0].fate != QuadOutcome::Fate::kNotDecoded) continue;  // refused earlier: nothing to complete
    const std::vector<Quad> completed = completed_quads(img, 6, std::vector<Quad>{q}, outcomes, {}, on());
    const auto again = decode_quads(img, completed, fams, 3, PayloadOptions{}, &area, nullptr, nullptr, true);
    ASSERT_EQ(again.size(), 1u) << k;
    EXPECT_EQ(again[0].id, kId);
    ++completed_and_read;
  }
  EXPECT_GE(completed_and_read, 2);  // the cut quads are read (not refused before), so this tests something
}

TEST(CornerCompletion, TheDetectorWithItOnFindsTheTagOnceAndInPlace) {
  const ImageF img = tag_image();
  DetectorOptions o;
  o.corner_completion.enabled = true;
  const auto got = Detector(o).detect(img);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].id, kId);
  EXPECT_LT(max_error(printed_corners(got[0].corners, 0), got[0].corners), 1e-12);
  double best = 1e9;
  for (int r = 0; r < 4; ++r) best = std::min(best, max_error(printed_corners(got[0].corners, r), truth()));
  EXPECT_LT(best, 0.3);
  // With none of the stages that keep every quad's outcome (the paper's profile): the completion keeps
  // them itself.
  DetectorOptions paper = DetectorOptions::paper();
  paper.corner_completion.enabled = true;
  const auto plain = Detector(paper).detect(img);
  ASSERT_EQ(plain.size(), 1u);
  EXPECT_EQ(plain[0].id, kId);
}

}  // namespace test_corner_completion
