#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "detect/printed_square.hpp"
#include "detect/quad_fit.hpp"
#include "synthetic_tag.hpp"

namespace test_printed_square {

using namespace tagbench;

// A printed 36h11 tag is 10 cells across, its black square 8: the square inside a 50 px printed
// square is 40 px, about the same centre, corners in the same order; 16h5 (d = 4): 6 / 8 of it.
TEST(PrintedSquare, BlackSquareIsTheInnerPartByPayloadWidth) {
  const Corners printed = synth::square_tag_corners(60, 50, 50, 0.3);
  const std::vector<Quad> quads{fitted_quad(printed)};
  const std::vector<int> widths{6, 4, 6};  // a repeated width gives one quad
  const auto inner = black_squares_in_printed_squares(quads, {true}, widths);
  ASSERT_EQ(inner.size(), 2u);
  const Corners want6 = synth::square_tag_corners(60, 50, 40, 0.3), want4 = synth::square_tag_corners(60, 50, 37.5, 0.3);
  EXPECT_LT(synth::corner_rms(inner[0].corners, want6), 1e-9);
  EXPECT_LT(synth::corner_rms(inner[1].corners, want4), 1e-9);
  EXPECT_EQ(inner[0].observed_perimeter, 0.0);
  // Under perspective the inner square follows the homography, not a shrink about the centroid.
  const Corners slanted{Eigen::Vector2d(10, 10), Eigen::Vector2d(70, 14), Eigen::Vector2d(66, 50), Eigen::Vector2d(14, 40)};
  const auto s = black_squares_in_printed_squares(std::vector<Quad>{fitted_quad(slanted)}, {true}, std::vector<int>{6});
  ASSERT_EQ(s.size(), 1u);
  const Eigen::Matrix3d H = *tag_homography(slanted);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LT((s[0].corners[k] - apply_homography(H, 0.8 * tag_square_corners()[k])).norm(), 1e-9);
}

TEST(PrintedSquare, OnlyLookedAtQuadsAndBadInputRefused) {
  const std::vector<Quad> quads{fitted_quad(synth::square_tag_corners(30, 30, 20, 0)),
                                fitted_quad({Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2),
                                         Eigen::Vector2d(3, 3)})};  // collinear: no homography
  EXPECT_TRUE(black_squares_in_printed_squares(quads, {false, true}, std::vector<int>{6}).empty());
  EXPECT_EQ(black_squares_in_printed_squares(quads, {true, true}, std::vector<int>{6}).size(), 1u);
  EXPECT_THROW(black_squares_in_printed_squares(quads, {true}, std::vector<int>{6}), std::invalid_argument);
  EXPECT_THROW(black_squares_in_printed_squares(quads, {true, false}, std::vector<int>{0}), std::invalid_argument);
}

// Grey paper on a white card: the local threshold classes the white ring with the black border and
// the only quad is the printed square's; the tag is found (with the other second chances off) only
// when that quad is also read as a printed square.
TEST(PrintedSquare, DetectorFindsATagWhoseRingIsDarkerThanItsCard) {
  const TagFamily fam = load_family("36h11");
  const Corners truth = synth::square_tag_corners(50, 48, 28, 0.2);
  const ImageF img = synth::render_tag(100, 96, tag_cells(fam, 77), synth::homography_for(truth), 0.95f, 8, 0.08f, 0.42f);
  DetectorOptions opt;
  opt.second_look.enabled = false;
  opt.code_refit.enabled = false;
  opt.line_quads.enabled = false;
  opt.dark_outlines.enabled = false;
  opt.printed_square.enabled = false;
  EXPECT_TRUE(Detector(opt).detect(img).empty());
  opt.printed_square.enabled = true;
  const auto found = Detector(opt).detect(img);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 77);
  EXPECT_LT(synth::corner_rms(found[0].corners, truth), 0.5);
  EXPECT_FALSE(DetectorOptions::paper().printed_square.enabled);
  EXPECT_TRUE(DetectorOptions().printed_square.enabled);
}

}  // namespace test_printed_square
