#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>
#include <stdexcept>

#include "detect/blur.hpp"
#include "detect/homography.hpp"
#include "detect/line_segments.hpp"
#include "synthetic_tag.hpp"

namespace test_line_segments {

using namespace tagbench;

namespace {

double distance_to_line(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  return std::abs(d.x() * (p - a).y() - d.y() * (p - a).x());
}

// The segment lying along side a -> b (either way) with its length and whether it runs a -> b.
struct Match {
  bool found = false, forward = false;
  double length = 0;
};
Match along(const std::vector<Segment>& segs, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  Match m;
  for (const Segment& s : segs) {
    if (distance_to_line(s.p0, a, b) > 1.0 || distance_to_line(s.p1, a, b) > 1.0) continue;
    const Eigen::Vector2d mid = (s.p0 + s.p1) / 2;
    if ((mid - (a + b) / 2).norm() > (b - a).norm() / 2) continue;
    if (s.length > m.length) m = {true, (s.p1 - s.p0).dot(b - a) > 0, s.length};
  }
  return m;
}

// The segment along each side of a 22 px square turned by phi, `inside` on `outside`.
std::array<Match, 4> side_matches(double phi, float outside, float inside, const LineSegmentOptions& o = {}) {
  const Corners c = synth::square_tag_corners(40, 40, 22, phi);
  LineSegmentScratch s;
  const auto segs = detect_line_segments(synth::filled_quad_image(80, c, outside, inside), o, s);
  std::array<Match, 4> m;
  for (int i = 0; i < 4; ++i) m[i] = along(segs, c[i], c[(i + 1) % 4]);
  return m;
}

}  // namespace

// Each side of a small turned dark square is one segment, dark on its left: around a dark square the
// segments run counter-clockwise on screen, i.e. against the corners' clockwise order.
TEST(LineSegments, FindsEachSideOfASmallSquareDarkOnTheLeft) {
  const auto m = side_matches(0.5, 0.8f, 0.2f);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(m[i].found) << "side " << i;
    EXPECT_FALSE(m[i].forward) << "side " << i;
    EXPECT_GT(m[i].length, 0.6 * 22) << "side " << i;
  }
}

// A light square: the same sides, the other way round.
TEST(LineSegments, LightSquareRunsTheOtherWay) {
  const auto m = side_matches(0.3, 0.25f, 0.7f);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(m[i].found) << "side " << i;
    EXPECT_TRUE(m[i].forward) << "side " << i;
  }
}

// The straight-edge check keeps a square's sides, whether it drops the pixels that fail it or only
// keeps them from seeding.
TEST(LineSegments, StraightCheckKeepsASquaresSides) {
  for (const bool seeds_only : {false, true})
    for (const int sides : {1, 2}) {
      LineSegmentOptions o;
      o.straight_sides = sides;
      o.straight_seeds_only = seeds_only;
      const auto m = side_matches(0.5, 0.8f, 0.2f, o);
      for (int i = 0; i < 4; ++i) {
        ASSERT_TRUE(m[i].found) << "side " << i << " sides " << sides << " seeds_only " << seeds_only;
        EXPECT_GT(m[i].length, 0.6 * 22) << "side " << i;  // as without the check
      }
    }
}

// Pixels dropped by the check take no part: the 6 px ends of a dark bar, under twice the reach,
// have no pixel with aligned pixels on both sides, so no segment, though each gives one unchecked.
TEST(LineSegments, StraightCheckDropsEdgesShorterThanItsReach) {
  ImageF img(40, 40, 0.8f);
  for (int y = 10; y < 30; ++y)
    for (int x = 17; x < 23; ++x) img.at(x, y) = 0.2f;  // a 6 x 20 bar
  LineSegmentScratch s;
  LineSegmentOptions o;
  o.min_length_px = 1;
  int vertical = 0, horizontal = 0;
  for (const Segment& g : detect_line_segments(img, o, s))
    (std::abs(g.p1.x() - g.p0.x()) > std::abs(g.p1.y() - g.p0.y()) ? horizontal : vertical)++;
  EXPECT_EQ(vertical, 2);
  EXPECT_EQ(horizontal, 2);
  o.straight_sides = 2;
  o.straight_check_px = 4;
  horizontal = vertical = 0;
  for (const Segment& g : detect_line_segments(img, o, s))
    (std::abs(g.p1.x() - g.p0.x()) > std::abs(g.p1.y() - g.p0.y()) ? horizontal : vertical)++;
  EXPECT_EQ(vertical, 2);
  EXPECT_EQ(horizontal, 0);
}

// LSD's a-contrario test: a flat image has no segment, and seeded noise (sigma 8 grey levels) next
// to none, where a low-contrast edge of 20 grey levels is still found.
TEST(LineSegments, NoSegmentsInFlatOrNoisyImagesButAFaintEdge) {
  LineSegmentScratch s;
  EXPECT_TRUE(detect_line_segments(ImageF(60, 60, 0.5f), LineSegmentOptions{}, s).empty());
  ImageF noise(200, 200);
  std::mt19937 rng(17);
  std::normal_distribution<float> n(0.5f, 8.0f / 255);
  for (auto& v : noise.data) v = n(rng);
  EXPECT_LE(detect_line_segments(noise, LineSegmentOptions{}, s).size(), 2u);
  const Corners c = synth::square_tag_corners(40, 40, 24, 0.2);
  const ImageF faint = synth::filled_quad_image(80, c, 0.55f, 0.55f - 20.0f / 255);
  const auto segs = detect_line_segments(faint, LineSegmentOptions{}, s);
  int sides = 0;
  for (int i = 0; i < 4; ++i) sides += along(segs, c[i], c[(i + 1) % 4]).found;
  EXPECT_EQ(sides, 4);
}

// The scratch is reused: a second image gives the same segments as a fresh scratch does.
TEST(LineSegments, ReusedScratchGivesTheSameSegments) {
  const ImageF a = synth::filled_quad_image(80, synth::square_tag_corners(40, 40, 22, 0.5), 0.8f, 0.2f);
  const ImageF b = synth::filled_quad_image(64, synth::square_tag_corners(30, 34, 18, 1.1), 0.3f, 0.9f);
  LineSegmentScratch warm, fresh;
  detect_line_segments(a, LineSegmentOptions{}, warm);
  const auto x = detect_line_segments(b, LineSegmentOptions{}, warm), y = detect_line_segments(b, LineSegmentOptions{}, fresh);
  ASSERT_EQ(x.size(), y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].p0, y[i].p0);
    EXPECT_EQ(x[i].p1, y[i].p1);
  }
}

// Skipping flat blocks is exact: on images flat in parts (a tag on a plain ground, a faint ramp and a faint box,
// noise in one corner, 8-bit levels as a camera gives them) the segments are those of every pixel
// differentiated, bit for bit, at several blurs.
TEST(LineSegments, SkippingFlatBlocksChangesNoSegment) {
  std::vector<ImageF> images;
  images.push_back(synth::filled_quad_image(150, synth::square_tag_corners(60, 70, 30, 0.4), 0.5f, 0.1f));
  ImageF ramp(250, 161);
  std::mt19937 rng(5);
  std::normal_distribution<float> n(0, 6.0f / 255);
  for (int y = 0; y < ramp.height; ++y)
    for (int x = 0; x < ramp.width; ++x) {
      float v = 0.5f + 0.02f * x / ramp.width + (x > 200 && y < 40 ? n(rng) : 0.0f);
      if (x > 30 && x < 70 && y > 30 && y < 60) v -= 0.2f;  // a dark box
      if (x > 130 && x < 190 && y > 90 && y < 140) v -= 5.0f / 255;  // a faint one: blocks near the limit
      ramp.at(x, y) = std::round(std::clamp(v, 0.0f, 1.0f) * 255) / 255;
    }
  images.push_back(ramp);
  ImageF quantised = images.front();
  for (float& v : quantised.data) v = std::round(v * 255) / 255;
  images.push_back(quantised);
  // A busy image first, so that the reused scratch holds directions where the flat images' far
  // blocks are left unwritten.
  ImageF busy(250, 161);
  for (float& v : busy.data) v = 0.5f + n(rng) * 4;
  images.insert(images.begin(), busy);
  int segments = 0;
  LineSegmentScratch s1;  // reused throughout
  for (const ImageF& img : images)
    for (double sigma : {0.0, 0.75, 3.0}) {
      LineSegmentOptions on, off;
      on.sigma = off.sigma = sigma;
      off.skip_flat_blocks = false;
      LineSegmentScratch s2;
      const auto a = detect_line_segments(img, on, s1), b = detect_line_segments(img, off, s2);
      ASSERT_EQ(a.size(), b.size()) << sigma;
      for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].p0, b[i].p0);
        EXPECT_EQ(a[i].p1, b[i].p1);
      }
      segments += static_cast<int>(a.size());
    }
  EXPECT_GT(segments, 20);
}

// Options that would divide by a zero gradient or break LSD's test are refused.
TEST(LineSegments, BadOptionsRefused) {
  LineSegmentScratch s;
  LineSegmentOptions o;
  o.min_gradient = 0;
  EXPECT_THROW(detect_line_segments(ImageF(20, 20, 0.5f), o, s), std::invalid_argument);
  o = LineSegmentOptions{};
  o.angle_tolerance_deg = 95;
  EXPECT_THROW(detect_line_segments(ImageF(20, 20, 0.5f), o, s), std::invalid_argument);
  o = LineSegmentOptions{};
  o.straight_sides = 3;
  EXPECT_THROW(detect_line_segments(ImageF(20, 20, 0.5f), o, s), std::invalid_argument);
  o = LineSegmentOptions{};
  o.straight_check_px = 0;
  EXPECT_THROW(detect_line_segments(ImageF(20, 20, 0.5f), o, s), std::invalid_argument);
}

}  // namespace test_line_segments
