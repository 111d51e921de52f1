#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "detect/blur.hpp"
#include "detect/line_fit.hpp"
#include "synthetic.hpp"

namespace test_line_fit {

using namespace tagbench;

namespace {
constexpr double kPi = std::numbers::pi;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double wrap(double a) { return std::remainder(a, 2 * kPi); }

// Pixels on the line through (0, 3) with direction (2, 1), each with the given gradient direction.
std::vector<ClusterPixel> line_pixels(float gradient_theta) {
  std::vector<ClusterPixel> px;
  for (int x = 0; x <= 10; x += 2) px.push_back({x, 3 + x / 2, 0.1f + 0.05f * x, gradient_theta});
  return px;
}

Clusters make_clusters(const std::vector<std::vector<ClusterPixel>>& list) {
  Clusters c;
  for (const auto& l : list) {
    c.pixels.insert(c.pixels.end(), l.begin(), l.end());
    c.offsets.push_back(c.pixels.size());
  }
  return c;
}

// The full front end at full resolution, or on the blurred half-resolution image mapped back.
std::vector<Segment> segments_of(const ImageF& img, bool decimate) {
  if (!decimate) return fit_segments(segment_clusters(compute_gradients(gaussian_blur(img, kSegSigma))));
  std::vector<Segment> s = fit_segments(segment_clusters(compute_gradients(blur_and_halve(img, kSegSigma))));
  for (Segment& seg : s) seg = segment_full_from_half(seg);
  return s;
}

std::vector<Segment> longer_than(const std::vector<Segment>& s, double len) {
  std::vector<Segment> out;
  for (const Segment& seg : s)
    if (seg.length > len) out.push_back(seg);
  return out;
}
}  // namespace

// The gradient (-sin a, cos a) points below-left of the line y = 3 + x / 2 (light below): walking
// with dark on the left means walking towards +x, since the left of +x is up on screen.
TEST(LineFit, FitsAnExactLineAndOrientsDarkOnTheLeft) {
  const double a = std::atan2(1.0, 2.0);
  const auto s = fit_segment(line_pixels(static_cast<float>(a + kPi / 2)));
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->p0.x(), 0.0, 1e-9);
  EXPECT_NEAR(s->p0.y(), 3.0, 1e-9);
  EXPECT_NEAR(s->p1.x(), 10.0, 1e-9);
  EXPECT_NEAR(s->p1.y(), 8.0, 1e-9);
  EXPECT_NEAR(s->theta, a, 1e-9);
  EXPECT_NEAR(s->length, std::sqrt(125.0), 1e-9);

  // The opposite gradient (light above) reverses the segment.
  const auto r = fit_segment(line_pixels(static_cast<float>(a - kPi / 2)));
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->p0.x(), 10.0, 1e-9);
  EXPECT_NEAR(r->p1.x(), 0.0, 1e-9);
  EXPECT_NEAR(wrap(r->theta - (a + kPi)), 0.0, 1e-9);
}

// Off-line pixels pull the fit by their weight: a heavy pixel row at y = 1 and a light one at
// y = 4 give the weighted mean row, with the endpoints spanning all the pixels' projections.
TEST(LineFit, WeightsAreTheGradientMagnitude) {
  std::vector<ClusterPixel> px;
  for (int x = 0; x <= 8; ++x) {
    px.push_back({x, 1, 0.3f, static_cast<float>(kPi / 2)});
    px.push_back({x, 4, 0.1f, static_cast<float>(kPi / 2)});
  }
  const auto s = fit_segment(px);
  ASSERT_TRUE(s);
  const double y = (0.3 * 1 + 0.1 * 4) / 0.4;  // 1.75 (the weights are floats: 1e-6 tolerance)
  EXPECT_NEAR(s->p0.y(), y, 1e-6);
  EXPECT_NEAR(s->p1.y(), y, 1e-6);
  // Gradient along +y (light below): the left of a walk towards +x is up on screen (-y), the dark
  // side, so the walk goes towards +x.
  EXPECT_NEAR(s->p0.x(), 0.0, 1e-9);
  EXPECT_NEAR(s->p1.x(), 8.0, 1e-9);
  EXPECT_NEAR(s->theta, 0.0, 1e-12);
}

TEST(LineFit, HorizontalWalkTowardsMinusXHasThetaPlusPi) {
  std::vector<ClusterPixel> px;
  for (int x = 0; x <= 8; ++x) px.push_back({x, 2, 0.2f, static_cast<float>(-kPi / 2)});  // light above
  const auto s = fit_segment(px);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->p0.x(), 8.0, 1e-9);
  EXPECT_DOUBLE_EQ(s->theta, kPi);  // not -pi
}

TEST(LineFit, EmptyOrWeightlessClustersHaveNoSegment) {
  EXPECT_FALSE(fit_segment({}));
  std::vector<ClusterPixel> px{{0, 0, 0.0f, 0.0f}, {1, 0, 0.0f, 0.0f}};
  EXPECT_FALSE(fit_segment(px));
}

TEST(LineFit, SegmentsShorterThanMinLengthAreDropped) {
  std::vector<ClusterPixel> short_run, long_run;
  for (int x = 0; x < 4; ++x) short_run.push_back({x, 0, 0.2f, static_cast<float>(kPi / 2)});  // length 3
  for (int x = 0; x < 6; ++x) long_run.push_back({x, 5, 0.2f, static_cast<float>(kPi / 2)});   // length 5
  const Clusters c = make_clusters({short_run, long_run});
  const std::vector<Segment> s = fit_segments(c);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].p0.y(), 5.0, 1e-9);
  EXPECT_NEAR(s[0].length, 5.0, 1e-9);
  EXPECT_EQ(fit_segments(c, LineFitOptions{2.0}).size(), 2u);
}

TEST(LineFit, SegmentFullFromHalfDoublesAndShiftsByHalfAPixel) {
  Segment s;
  s.p0 = {1.0, 2.0};
  s.p1 = {4.0, 6.0};
  s.theta = std::atan2(4.0, 3.0);
  s.length = 5.0;
  const Segment f = segment_full_from_half(s);
  EXPECT_DOUBLE_EQ(f.p0.x(), 2.5);
  EXPECT_DOUBLE_EQ(f.p0.y(), 4.5);
  EXPECT_DOUBLE_EQ(f.p1.x(), 8.5);
  EXPECT_DOUBLE_EQ(f.p1.y(), 12.5);
  EXPECT_DOUBLE_EQ(f.length, 10.0);
  EXPECT_DOUBLE_EQ(f.theta, s.theta);
  EXPECT_NEAR((f.p1 - f.p0).norm(), f.length, 1e-12);
}

namespace {

// Follows the segments as the quad search will (from each end to the nearest start) and sums
// the turning angles: about -2 pi for segments winding counter-clockwise on screen (y down).
double winding_by_chaining(const std::vector<Segment>& segs) {
  double turning = 0.0;
  std::size_t cur = 0;
  std::vector<bool> used(segs.size(), false);
  for (std::size_t step = 0; step < segs.size(); ++step) {
    used[cur] = true;
    std::size_t next = 0;
    double best = 1e300;
    for (std::size_t j = 0; j < segs.size(); ++j) {
      const double d = (segs[j].p0 - segs[cur].p1).norm();
      if (j != cur && d < best && (!used[j] || (j == 0 && step + 1 == segs.size()))) {
        best = d;
        next = j;
      }
    }
    EXPECT_LT(best, 5.0) << "segment " << cur << " ends far from any start";
    const Eigen::Vector2d ds = segs[cur].p1 - segs[cur].p0, dt = segs[next].p1 - segs[next].p0;
    turning += std::atan2(cross(ds, dt), ds.dot(dt));
    cur = next;
  }
  EXPECT_EQ(cur, 0u) << "the chain does not close";
  return turning;
}

// Where the infinite lines of two segments cross.
Eigen::Vector2d intersection(const Segment& s, const Segment& t) {
  const Eigen::Vector2d d1 = s.p1 - s.p0, d2 = t.p1 - t.p0;
  return s.p0 + cross(t.p0 - s.p0, d2) / cross(d1, d2) * d1;
}

}  // namespace

// The whole front end on a rendered dark square, at full resolution and decimated: four long
// segments along the true sides, each with the dark interior on its left, winding counter-clockwise
// on screen (turning angles sum to -2 pi in image coordinates).
//
// Ends: the pixels right at a corner have turning gradient directions and go to small corner
// clusters, so at full resolution a side's segment stops short of the corner, by up to ~2 px
// (measured over 0..90 deg). Decimated, the edge band is ~8 full-resolution px wide and its outer
// pixels project past the corner, so the ends land up to ~2.5 px either side of it. The quad stage takes corners from line intersections, which are far more precise
// (paper: "a small fraction of a pixel"): that is asserted too.
class SquareFrontEnd : public ::testing::TestWithParam<std::tuple<bool, double>> {};

TEST_P(SquareFrontEnd, DarkSquareSegmentsFollowTheSidesWithDarkOnTheLeft) {
  const auto [decimate, degrees] = GetParam();
  const double phi = degrees * kPi / 180;
  const auto corners = synth::square_corners_ccw({80.3, 78.7}, 30.0, phi);
  const ImageF img = synth::render_convex_polygon(160, 160, {corners.begin(), corners.end()}, 0.15f, 0.85f);
  const std::vector<Segment> segs = longer_than(segments_of(img, decimate), 20.0);
  ASSERT_EQ(segs.size(), 4u);

  // Match each segment with the side corner[k] -> corner[k+1] it runs along, in that direction.
  std::array<int, 4> seg_of_side{-1, -1, -1, -1};
  // Allowed distance of an end from its corner along the side, inwards and outwards.
  const double inwards = decimate ? 3.0 : 2.2, outwards = decimate ? 3.0 : 0.5;
  for (int i = 0; i < 4; ++i) {
    const Segment& s = segs[i];
    int best = -1;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d side = corners[(k + 1) % 4] - corners[k];
      if (std::abs(wrap(s.theta - std::atan2(side.y(), side.x()))) < (decimate ? 0.3 : 0.1) * kPi / 180) best = k;
    }
    ASSERT_GE(best, 0) << "segment " << i << " theta " << s.theta << " is not along a side, dark on the left";
    seg_of_side[best] = i;
    const Eigen::Vector2d a = corners[best], b = corners[(best + 1) % 4];
    const Eigen::Vector2d u = (b - a).normalized();
    // Both ends lie on the true side's line to within a small fraction of a pixel...
    EXPECT_LT(std::abs(cross(u, s.p0 - a)), 0.15) << "side " << best;
    EXPECT_LT(std::abs(cross(u, s.p1 - a)), 0.15) << "side " << best;
    // ...and within a few pixels of the true corners along it.
    EXPECT_GT(u.dot(s.p0 - a), -outwards) << "side " << best << " start " << s.p0.transpose();
    EXPECT_LT(u.dot(s.p0 - a), inwards) << "side " << best << " start " << s.p0.transpose();
    EXPECT_LT(u.dot(s.p1 - b), outwards) << "side " << best << " end " << s.p1.transpose();
    EXPECT_GT(u.dot(s.p1 - b), -inwards) << "side " << best << " end " << s.p1.transpose();
    // "Dark on the left" directly: a step to the left of the midpoint is dark, to the right light.
    const Eigen::Vector2d mid = 0.5 * (s.p0 + s.p1), d = (s.p1 - s.p0).normalized();
    const Eigen::Vector2d left(d.y(), -d.x());  // the on-screen left with y down
    const Eigen::Vector2d in = mid + 4 * left, out = mid - 4 * left;
    EXPECT_LT(img.at(static_cast<int>(std::lround(in.x())), static_cast<int>(std::lround(in.y()))), 0.5f);
    EXPECT_GT(img.at(static_cast<int>(std::lround(out.x())), static_cast<int>(std::lround(out.y()))), 0.5f);
  }
  for (int k = 0; k < 4; ++k) {
    ASSERT_GE(seg_of_side[k], 0) << "no segment on side " << k;
    const Segment& s = segs[seg_of_side[(k + 3) % 4]];  // the side ending at corner k
    const Segment& t = segs[seg_of_side[k]];            // the side starting there
    EXPECT_LT(cross(s.p1 - s.p0, t.p1 - t.p0), 0.0);   // every turn is the same way
    EXPECT_LT((intersection(s, t) - corners[k]).norm(), decimate ? 0.2 : 0.15) << "corner " << k;
  }
  EXPECT_NEAR(winding_by_chaining(segs), -2 * kPi, 0.05);
}

INSTANTIATE_TEST_SUITE_P(FullAndHalfResolution, SquareFrontEnd,
                         ::testing::Combine(::testing::Bool(), ::testing::Values(0.0, 20.0, 45.0, 71.0)));

// Reversing the contrast reverses every segment, so the winding changes sign.
TEST(LineFit, LightSquareOnDarkWindsTheOtherWay) {
  const auto corners = synth::square_corners_ccw({60.0, 61.0}, 25.0, -0.3);
  const std::vector<Eigen::Vector2d> poly(corners.begin(), corners.end());
  const ImageF light = synth::render_convex_polygon(120, 120, poly, 0.9f, 0.1f);
  const ImageF dark = synth::render_convex_polygon(120, 120, poly, 0.1f, 0.9f);
  const std::vector<Segment> ls = longer_than(segments_of(light, false), 20.0);
  const std::vector<Segment> ds = longer_than(segments_of(dark, false), 20.0);
  ASSERT_EQ(ls.size(), 4u);
  ASSERT_EQ(ds.size(), 4u);
  EXPECT_NEAR(winding_by_chaining(ls), 2 * kPi, 0.05);
  EXPECT_NEAR(winding_by_chaining(ds), -2 * kPi, 0.05);
}

// Blurring before segmentation is what keeps noise from making lines (paper section III-A):
// noise of 0.05 (on a [0, 1] image) gives hundreds of short segments unblurred, and after the
// sigma = 0.8 blur almost none, none of them long.
TEST(LineFit, NoiseOnlyImageGivesNoLongSegmentsAfterBlurring) {
  ImageF img(200, 200, 0.5f);
  synth::add_gaussian_noise(img, 0.05, 5);
  auto longest = [](const std::vector<Segment>& segs) {
    double l = 0.0;
    for (const Segment& s : segs) l = std::max(l, s.length);
    return l;
  };
  const std::vector<Segment> blurred = segments_of(img, false);
  EXPECT_LT(blurred.size(), 10u);
  EXPECT_LT(longest(blurred), 8.0);
  const std::vector<Segment> raw = fit_segments(segment_clusters(compute_gradients(img)));
  EXPECT_GT(raw.size(), 100u);  // the same noise, unblurred
}

}  // namespace test_line_fit
