#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "detect/homography.hpp"

namespace test_homography {

using namespace tagbench;

TEST(Homography, RoundTripOfAKnownHomography) {
  Eigen::Matrix3d H;
  H << 120, 15, 320, -10, 110, 240, 0.05, -0.03, 1;
  std::vector<Eigen::Vector2d> from, to;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 12; ++i) {
    from.emplace_back(u(rng), u(rng));
    to.push_back(apply_homography(H, from.back()));
  }
  for (const std::size_t n : {4u, 12u}) {
    const auto E = homography_dlt(std::span(from).first(n), std::span(to).first(n));
    ASSERT_TRUE(E.has_value());
    for (std::size_t i = 0; i < from.size(); ++i)
      EXPECT_LT((apply_homography(*E, from[i]) - to[i]).norm(), 1e-8) << n << " points";
    EXPECT_NEAR(E->norm(), 1.0, 1e-12);
    EXPECT_NEAR((*E / (*E)(2, 2) - H).norm(), 0, 1e-6);
  }
}

TEST(Homography, TagSquareCornersMapToTheImageCorners) {
  const Corners img = {Eigen::Vector2d(100.25, 50.5), Eigen::Vector2d(180, 60), Eigen::Vector2d(175, 140),
                       Eigen::Vector2d(95, 130)};
  const auto H = tag_homography(img);
  ASSERT_TRUE(H.has_value());
  for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((apply_homography(*H, tag_square_corners()[i]) - img[i]).norm(), 1e-9);
  // The tag centre goes to the intersection of the diagonals.
  const Eigen::Vector2d c = apply_homography(*H, Eigen::Vector2d(0, 0));
  const Eigen::Vector2d d1 = img[2] - img[0], d2 = img[3] - img[1];
  Eigen::Matrix2d A;
  A << d1, -d2;
  const Eigen::Vector2d st = A.colPivHouseholderQr().solve(img[1] - img[0]);
  EXPECT_LT((c - (img[0] + st(0) * d1)).norm(), 1e-9);
}

TEST(Homography, DegenerateInputIsRefused) {
  const Corners collinear = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 3)};
  EXPECT_FALSE(tag_homography(collinear).has_value());
  const Corners same = {Eigen::Vector2d(5, 5), Eigen::Vector2d(5, 5), Eigen::Vector2d(5, 5), Eigen::Vector2d(5, 5)};
  EXPECT_FALSE(tag_homography(same).has_value());
  std::vector<Eigen::Vector2d> three(3, Eigen::Vector2d(1, 2));
  EXPECT_FALSE(homography_dlt(three, three).has_value());
}

// inside_quad: either winding, a point on a side inside; a NaN anywhere or corners on one line: never
// inside (a NaN compares false, which read as inside before session 31).
TEST(Homography, InsideQuad) {
  const Corners cw{Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 0), Eigen::Vector2d(10, 10), Eigen::Vector2d(0, 10)};
  const Corners ccw{cw[0], cw[3], cw[2], cw[1]};
  for (const Corners& q : {cw, ccw}) {
    EXPECT_TRUE(inside_quad(q, Eigen::Vector2d(5, 5)));
    EXPECT_TRUE(inside_quad(q, Eigen::Vector2d(0.5, 9.5)));
    EXPECT_FALSE(inside_quad(q, Eigen::Vector2d(11, 5)));
    EXPECT_FALSE(inside_quad(q, Eigen::Vector2d(5, -0.5)));
    EXPECT_FALSE(inside_quad(q, Eigen::Vector2d(std::nan(""), 5)));
  }
  EXPECT_TRUE(inside_quad(cw, Eigen::Vector2d(10, 5)));  // on a side (of this winding)
  Corners with_nan = cw;
  with_nan[2].x() = std::nan("");
  EXPECT_FALSE(inside_quad(with_nan, Eigen::Vector2d(5, 5)));
  const Corners line{Eigen::Vector2d(-5, 0), Eigen::Vector2d(0, 0), Eigen::Vector2d(5, 0), Eigen::Vector2d(0, 0)};
  EXPECT_FALSE(inside_quad(line, Eigen::Vector2d(0, 0)));
  EXPECT_FALSE(inside_quad(line, Eigen::Vector2d(2, 0)));
}

// The row-wise test answers as inside_quad for every pixel of a scan, on random quads (convex,
// concave, either winding, corners on the pixel grid so that pixels fall exactly on sides), the
// degenerate line and a quad with a NaN corner.
TEST(Homography, QuadRowTestAnswersAsInsideQuad) {
  std::mt19937 rng(38);
  std::uniform_real_distribution<double> u(-3, 23);
  std::uniform_int_distribution<int> k(-3, 23);
  std::vector<Corners> quads;
  for (int i = 0; i < 200; ++i) {
    Corners q;
    for (auto& p : q) p = i % 2 ? Eigen::Vector2d(u(rng), u(rng)) : Eigen::Vector2d(k(rng), k(rng));
    quads.push_back(q);
  }
  quads.push_back({Eigen::Vector2d(-5, 0), Eigen::Vector2d(0, 0), Eigen::Vector2d(5, 0), Eigen::Vector2d(0, 0)});
  Corners with_nan = quads.front();
  with_nan[1].y() = std::nan("");
  quads.push_back(with_nan);
  int inside = 0, outside = 0;
  for (const Corners& q : quads) {
    QuadRowTest t(q);
    for (int y = -4; y <= 24; ++y) {
      t.row(y);
      for (int x = -4; x <= 24; ++x) {
        const bool want = inside_quad(q, Eigen::Vector2d(x, y));
        ASSERT_EQ(t.contains(x), want) << x << "," << y;
        (want ? inside : outside)++;
      }
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

#if defined(__SSE2__)
// The two-point map gives apply_homography's doubles bit for bit (random perspective homographies).
TEST(Homography, PairMapEqualsApplyHomographyBitForBit) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2, 2), h(-500, 500);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix3d H;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) H(r, c) = h(rng);
    H(2, 0) = 0.01 * u(rng), H(2, 1) = 0.01 * u(rng), H(2, 2) = 1 + 0.1 * u(rng);
    const Eigen::Vector2d a(u(rng), u(rng)), b(u(rng), u(rng));
    __m128d x, y;
    apply_homography_pair(H, _mm_set_pd(b.x(), a.x()), _mm_set_pd(b.y(), a.y()), x, y);
    alignas(16) double xs[2], ys[2];
    _mm_store_pd(xs, x);
    _mm_store_pd(ys, y);
    const Eigen::Vector2d pa = apply_homography(H, a), pb = apply_homography(H, b);
    EXPECT_EQ(xs[0], pa.x());
    EXPECT_EQ(ys[0], pa.y());
    EXPECT_EQ(xs[1], pb.x());
    EXPECT_EQ(ys[1], pb.y());
  }
}
#endif

}  // namespace test_homography
