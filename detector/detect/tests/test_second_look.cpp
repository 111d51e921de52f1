#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "detect/detector.hpp"
#include "detect/second_look.hpp"
#include "card_scene.hpp"

namespace test_second_look {

using namespace tagbench;

namespace {
using tagbench::test_scenes::card_scene;
using tagbench::test_scenes::square_quad;
using tagbench::test_scenes::worst_corner_error;
}  // namespace

TEST(SecondLook, OtsuSplitsTwoLevelsBetweenThem) {
  std::vector<float> v(100, 0.2f);
  v.insert(v.end(), 50, 0.6f);
  const OtsuSplit s = otsu_split(v);
  EXPECT_GT(s.threshold, 0.2);
  EXPECT_LT(s.threshold, 0.6);
  EXPECT_NEAR(s.dark_mean, 0.2, 0.003);
  EXPECT_NEAR(s.light_mean, 0.6, 0.003);
  const OtsuSplit flat = otsu_split(std::vector<float>(10, 0.5f));
  EXPECT_NEAR(flat.light_mean - flat.dark_mean, 0, 1e-12);
}

// The quad handed in is the card's outline (what the local threshold gives when the ring merges
// with the card); one threshold for the region separates the ink from the card and finds the square.
TEST(SecondLook, FindsTheDarkSquareInsideALighterCardsQuad) {
  const ImageF img = card_scene(0.30f, 0.42f, 0.31f, 20, 34, 27, 20);  // low contrast: 0.11 between card and ink
  const Quad card = square_quad(19.5, 53.5);
  ThresholdQuadOptions tq;
  SecondLookOptions opt;
  const auto quads = second_look_quads(img, std::span(&card, 1), {true}, tq, opt);
  ASSERT_FALSE(quads.empty());
  double best = HUGE_VAL;
  for (const Quad& q : quads) best = std::min(best, worst_corner_error(q.corners, square_quad(26.5, 46.5).corners));
  EXPECT_LT(best, 0.3);
}

TEST(SecondLook, SkipsQuadsNotAskedForTooLargeOrFlat) {
  const ImageF img = card_scene(0.30f, 0.42f, 0.31f, 20, 34, 27, 20);
  const Quad card = square_quad(19.5, 53.5);
  ThresholdQuadOptions tq;
  SecondLookOptions opt;
  EXPECT_TRUE(second_look_quads(img, std::span(&card, 1), {false}, tq, opt).empty());
  opt.max_size_px = 30;  // the card is 34 px
  EXPECT_TRUE(second_look_quads(img, std::span(&card, 1), {true}, tq, opt).empty());
  opt.max_size_px = 64;
  opt.min_size_px = 35;  // too small now
  EXPECT_TRUE(second_look_quads(img, std::span(&card, 1), {true}, tq, opt).empty());
  opt.min_size_px = 34;
  EXPECT_FALSE(second_look_quads(img, std::span(&card, 1), {true}, tq, opt).empty());
  const ImageF flat(80, 80, 0.4f);
  EXPECT_TRUE(second_look_quads(flat, std::span(&card, 1), {true}, tq, SecondLookOptions{}).empty());
}

// A quad already on the square gives nothing new (every corner within min_corner_change_px).
TEST(SecondLook, DropsAQuadThatMatchesTheOldOne) {
  const ImageF img = card_scene(0.30f, 0.42f, 0.31f, 20, 34, 27, 20);
  const Quad on_square = square_quad(26.5, 46.5);
  ThresholdQuadOptions tq;
  const auto quads = second_look_quads(img, std::span(&on_square, 1), {true}, tq, SecondLookOptions{});
  for (const Quad& q : quads) EXPECT_GT(worst_corner_error(q.corners, on_square.corners), 1.0);
}

// A light card on a much darker ground: Otsu over the whole region splits ground from card and ink
// together, over the inside of the card's quad it splits the ink from the card (inside_only).
TEST(SecondLook, InsideOnlySplitsInkFromCardOnADarkGround) {
  const ImageF img = card_scene(0.10f, 0.60f, 0.45f, 20, 34, 27, 20);
  const Quad card = square_quad(19.5, 53.5);
  const Corners want = square_quad(26.5, 46.5).corners;
  ThresholdQuadOptions tq;
  const auto best_error = [&](bool inside_only) {
    SecondLookOptions opt;
    opt.inside_only = inside_only;
    double best = HUGE_VAL;
    for (const Quad& q : second_look_quads(img, std::span(&card, 1), {true}, tq, opt))
      best = std::min(best, worst_corner_error(q.corners, want));
    return best;
  };
  EXPECT_LT(best_error(true), 0.3);
  EXPECT_GT(best_error(false), 2.0);
}

// The options' domains (DetectorOptions::validate names the field).
TEST(SecondLook, ValidateRefusesOptionsOutOfRange) {
  DetectorOptions o;
  o.second_look.max_size_px = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.second_look.min_class_gap = 1.5;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = DetectorOptions{};
  o.second_look.margin_px = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  DetectorOptions{}.validate();
}

// Which quads are looked at again: those that did not decode; with skip_border_rejected not those
// the border pre-filter refused.
TEST(SecondLook, LooksAtUndecodedQuadsAndOptionallyNotAtRefusedOnes) {
  SecondLookOptions o;
  EXPECT_FALSE(wants_second_look(true, false, o));
  EXPECT_TRUE(wants_second_look(false, false, o));
  EXPECT_TRUE(wants_second_look(false, true, o));
  o.skip_border_rejected = true;
  EXPECT_FALSE(wants_second_look(true, false, o));
  EXPECT_TRUE(wants_second_look(false, false, o));
  EXPECT_FALSE(wants_second_look(false, true, o));
  EXPECT_TRUE(DetectorOptions{}.second_look.skip_border_rejected);  // the default profile
}

}  // namespace test_second_look
