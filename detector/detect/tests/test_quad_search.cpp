#include <gtest/gtest.h>

#include "detect/blur.hpp"
#include "detect/gradient.hpp"
#include "detect/quad_search.hpp"
#include "detect/segmentation.hpp"
#include "synthetic.hpp"

namespace test_quad_search {

using namespace tagbench;

namespace {
// Four segments around the square with corners c (counter-clockwise on screen), shortened by `gap`
// at both ends, dark on the left.
std::vector<Segment> sides(const std::array<Eigen::Vector2d, 4>& c, double gap) {
  std::vector<Segment> s;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = c[static_cast<std::size_t>(i)], b = c[static_cast<std::size_t>((i + 1) % 4)];
    const Eigen::Vector2d u = (b - a).normalized();
    Segment seg;
    seg.p0 = a + gap * u;
    seg.p1 = b - gap * u;
    seg.theta = std::atan2(u.y(), u.x());
    seg.length = (seg.p1 - seg.p0).norm();
    s.push_back(seg);
  }
  return s;
}
}  // namespace

TEST(QuadSearch, FindsTheSquareOnceWithCornersAtTheLineIntersections) {
  const auto c = synth::square_corners_ccw(Eigen::Vector2d(50, 40), 20, 0.3);
  const auto quads = find_quads(sides(c, 3.0));
  ASSERT_EQ(quads.size(), 1u);
  // Corners come out clockwise on screen: the reverse of the counter-clockwise input.
  for (std::size_t i = 0; i < 4; ++i) {
    double best = 1e9;
    for (const auto& q : quads[0].corners) best = std::min(best, (q - c[i]).norm());
    EXPECT_LT(best, 1e-9);
  }
  const auto& q = quads[0].corners;
  const double cross01 = (q[1] - q[0]).x() * (q[2] - q[1]).y() - (q[1] - q[0]).y() * (q[2] - q[1]).x();
  EXPECT_GT(cross01, 0) << "clockwise on screen (y down) has a positive cross product";
}

TEST(QuadSearch, WrongWindingIsNoQuad) {
  const auto c = synth::square_corners_ccw(Eigen::Vector2d(50, 40), 20, 0.0);
  auto s = sides(c, 2.0);
  for (auto& seg : s) {  // light on the left: a light square on a dark background
    std::swap(seg.p0, seg.p1);
    seg.theta = std::atan2((seg.p1 - seg.p0).y(), (seg.p1 - seg.p0).x());
  }
  // With the paper's generous radius (2 x length + 5) the reversed sides can still chain across the
  // square in a consistently turning order, and the quad is left for the decoder's contrast check to
  // reject; with a radius that only bridges real corners, the winding rule alone refuses it.
  QuadSearchOptions tight;
  tight.close_enough = CloseEnoughRule::kCode2012;
  EXPECT_TRUE(find_quads(s, tight).empty());
  EXPECT_EQ(find_quads(sides(c, 2.0), tight).size(), 1u);
}

TEST(QuadSearch, CloseEnoughRuleDecidesOcclusionTolerance) {
  // Sides of length 40 with one side 14 px short at its end: a large gap the paper's rule bridges
  // (2 x 12 + 5) but the 2010 code's rule (0.5 x length) does not.
  const auto c = synth::square_corners_ccw(Eigen::Vector2d(60, 60), 20, 0.0);
  auto s = sides(c, 1.0);
  const Eigen::Vector2d u = (s[1].p1 - s[1].p0).normalized();
  s[1].p1 -= 25.0 * u;  // occluded: only 13 px of this side remain
  s[1].length = (s[1].p1 - s[1].p0).norm();
  QuadSearchOptions paper, old;
  old.close_enough = CloseEnoughRule::kCode2010;
  EXPECT_EQ(find_quads(s, paper).size(), 1u);
  EXPECT_TRUE(find_quads(s, old).empty());
  EXPECT_DOUBLE_EQ(close_enough_radius(CloseEnoughRule::kCode2012, 10), 11);
}

TEST(QuadSearch, TooSmallOrTooThinQuadsAreRejected) {
  EXPECT_TRUE(find_quads(sides(synth::square_corners_ccw(Eigen::Vector2d(10, 10), 2, 0.0), 0.2)).empty());
  const std::array<Eigen::Vector2d, 4> thin = {Eigen::Vector2d(100, 10), Eigen::Vector2d(0, 10), Eigen::Vector2d(0, 12.5),
                                               Eigen::Vector2d(100, 12.5)};
  EXPECT_TRUE(find_quads(sides(thin, 0.2)).empty());
}

TEST(QuadSearch, FromARenderedDarkSquare) {
  const auto c = synth::square_corners_ccw(Eigen::Vector2d(40.3, 35.7), 18, 0.4);
  const ImageF img = synth::render_convex_polygon(80, 72, {c.begin(), c.end()}, 0.1f, 0.9f);
  const auto g = compute_gradients(gaussian_blur(img, 0.8), 0.004f);
  const auto quads = find_quads(fit_segments(segment_clusters(g)));
  ASSERT_GE(quads.size(), 1u);
  for (std::size_t i = 0; i < 4; ++i) {
    double best = 1e9;
    for (const auto& q : quads[0].corners) best = std::min(best, (q - c[i]).norm());
    EXPECT_LT(best, 0.2);
  }
}

}  // namespace test_quad_search
