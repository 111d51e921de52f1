#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>

#include "detect/blur.hpp"
#include "detect/segmentation.hpp"
#include "synthetic.hpp"

namespace test_segmentation {

using namespace tagbench;

namespace {
constexpr float kPi = std::numbers::pi_v<float>;

ComponentStats stats(std::uint32_t size, float tmin, float tmax, float mmin, float mmax) {
  return {size, tmin, tmax, mmin, mmax};
}

// A uniform gradient field: every pixel has the same magnitude and direction.
Gradients flat_field(int w, int h, float mag, float theta) {
  Gradients g;
  g.width = w;
  g.height = h;
  g.mag.assign(static_cast<std::size_t>(w * h), mag);
  g.theta.assign(static_cast<std::size_t>(w * h), theta);
  return g;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> edge_set(const std::vector<GraphEdge>& edges) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> s;
  for (const GraphEdge& e : edges) s.insert({std::min(e.a, e.b), std::max(e.a, e.b)});
  return s;
}

Clusters segment_image(const ImageF& img) {
  return segment_clusters(compute_gradients(gaussian_blur(img, kSegSigma)));
}
}  // namespace

TEST(Segmentation, AngleDistanceWrapsIntoZeroToPi) {
  EXPECT_NEAR(angle_distance(0.1f, -0.1f), 0.2f, 1e-6);
  EXPECT_NEAR(angle_distance(3.1f, -3.1f), 2 * kPi - 6.2f, 1e-5);
  EXPECT_NEAR(angle_distance(kPi, -kPi), 0.0f, 1e-6);
  EXPECT_NEAR(angle_distance(kPi / 2, -kPi / 2), kPi, 1e-6);
  EXPECT_NEAR(angle_distance(-2.0f, 2.0f), 2 * kPi - 4.0f, 1e-5);
}

TEST(Segmentation, EdgesJoinAllEightNeighboursOnceWithZeroWeightForEqualDirections) {
  const Gradients g = flat_field(3, 3, 0.5f, 1.0f);
  const std::vector<GraphEdge> edges = build_edges(g);
  // 3x3 grid: 6 horizontal, 6 vertical, 4 diagonal, 4 anti-diagonal pairs.
  EXPECT_EQ(edges.size(), 20u);
  EXPECT_EQ(edge_set(edges).size(), 20u);  // no pair twice
  for (const GraphEdge& e : edges) {
    EXPECT_EQ(e.weight, 0u);
    const int ax = static_cast<int>(e.a % 3), ay = static_cast<int>(e.a / 3);
    const int bx = static_cast<int>(e.b % 3), by = static_cast<int>(e.b / 3);
    EXPECT_LE(std::max(std::abs(ax - bx), std::abs(ay - by)), 1);  // 8-neighbours only
  }
}

TEST(Segmentation, EdgesNeedBothPixelsAboveMinMagAndDirectionsWithinMaxCost) {
  const SegmentationOptions opt;
  Gradients g = flat_field(3, 3, 0.5f, 0.0f);
  g.mag[4] = opt.min_mag;  // the centre is not strictly above min_mag: no edge touches it
  g.theta[0] = static_cast<float>(40 * std::numbers::pi / 180);  // 40 deg from everyone: isolated
  g.theta[8] = static_cast<float>(15 * std::numbers::pi / 180);  // 15 deg: half the max cost
  const std::vector<GraphEdge> edges = build_edges(g, opt);
  for (const GraphEdge& e : edges) {
    EXPECT_NE(e.a, 4u);
    EXPECT_NE(e.b, 4u);
    EXPECT_NE(e.a, 0u);
    EXPECT_NE(e.b, 0u);
    const std::uint32_t expected = (e.a == 8 || e.b == 8) ? 50u : 0u;  // (int)(15 / 30 * 100)
    EXPECT_EQ(e.weight, expected) << e.a << "-" << e.b;
  }
  // What is left: every 8-neighbour pair that avoids pixels 0 and 4 (the grid is
  //   0 1 2 / 3 4 5 / 6 7 8).
  EXPECT_EQ(edge_set(edges), (std::set<std::pair<std::uint32_t, std::uint32_t>>{
                                 {1, 2}, {6, 7}, {7, 8}, {3, 6}, {2, 5}, {5, 8}, {1, 5}, {3, 7}, {1, 3}, {5, 7}}));
}

TEST(Segmentation, EdgeWeightsAcrossThePiWrapAreSmall) {
  Gradients g = flat_field(2, 1, 0.5f, 3.1f);
  g.theta[1] = -3.1f;  // 0.083 rad away through +-pi, not 6.2
  const std::vector<GraphEdge> edges = build_edges(g);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].weight, static_cast<std::uint32_t>((2 * kPi - 6.2f) / (kPi / 6) * 100));
  EXPECT_LE(edges[0].weight, 16u);
}

TEST(Segmentation, CountingSortIsSortedAndStable) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> w(0, 100);
  std::vector<GraphEdge> edges(5000);
  for (std::uint32_t i = 0; i < edges.size(); ++i) edges[i] = {i, i + 1, w(rng)};  // a records input order
  const std::vector<GraphEdge> sorted = counting_sort_edges(edges, 100);
  ASSERT_EQ(sorted.size(), edges.size());
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    ASSERT_LE(sorted[i - 1].weight, sorted[i].weight);
    if (sorted[i - 1].weight == sorted[i].weight) {
      ASSERT_LT(sorted[i - 1].a, sorted[i].a) << "not stable";
    }
  }
  std::vector<GraphEdge> ref = edges;
  std::stable_sort(ref.begin(), ref.end(), [](const GraphEdge& x, const GraphEdge& y) { return x.weight < y.weight; });
  for (std::size_t i = 0; i < ref.size(); ++i) ASSERT_EQ(sorted[i].a, ref[i].a);

  EXPECT_TRUE(counting_sort_edges({}, 100).empty());
  EXPECT_THROW(counting_sort_edges({{0, 1, 101}}, 100), std::invalid_argument);
}

// Two components whose union is about as uniform as each of them: (1) and (2) both pass.
TEST(Segmentation, MergeRuleJoinsSimilarComponents) {
  const ComponentStats n = stats(10, 0.10f, 0.20f, 0.50f, 0.60f);
  const ComponentStats m = stats(10, 0.15f, 0.22f, 0.55f, 0.62f);
  // D(u) = 0.12 <= min(0.10, 0.07) + 2 / 20 = 0.17, M(u) = 0.12 <= 0.07 + 0.1
  const auto u = try_union(n, m, 2.0, 2.0);
  ASSERT_TRUE(u);
  EXPECT_EQ(u->size, 20u);
  EXPECT_FLOAT_EQ(u->theta_min, 0.10f);
  EXPECT_FLOAT_EQ(u->theta_max, 0.22f);
  EXPECT_FLOAT_EQ(u->mag_min, 0.50f);
  EXPECT_FLOAT_EQ(u->mag_max, 0.62f);
  // Symmetric in its arguments.
  const auto v = try_union(m, n, 2.0, 2.0);
  ASSERT_TRUE(v);
  EXPECT_FLOAT_EQ(v->theta_range(), u->theta_range());
}

// Test (1) alone rejects: directions too far apart for the allowance K_D / |n u m|.
TEST(Segmentation, MergeRuleRejectsDifferentDirections) {
  const ComponentStats n = stats(10, 0.10f, 0.20f, 0.50f, 0.60f);
  const ComponentStats m = stats(10, 0.30f, 0.35f, 0.50f, 0.60f);
  // D(u) = 0.25 > min(0.10, 0.05) + 2 / 20 = 0.15 ...
  EXPECT_FALSE(try_union(n, m, 2.0, 2.0));
  // ... but a larger K_D (0.05 + 6 / 20 = 0.35) admits it: the rejection came from test (1).
  EXPECT_TRUE(try_union(n, m, 6.0, 2.0));
}

// Test (2) alone rejects: magnitudes too different, directions identical.
TEST(Segmentation, MergeRuleRejectsDifferentMagnitudes) {
  const ComponentStats n = stats(10, 0.10f, 0.20f, 0.50f, 0.60f);
  const ComponentStats m = stats(10, 0.10f, 0.20f, 1.50f, 1.60f);
  EXPECT_FALSE(try_union(n, m, 2.0, 2.0));  // M(u) = 1.1 > 0.1 + 0.1
  EXPECT_TRUE(try_union(n, m, 2.0, 30.0));  // 1.1 <= 0.1 + 1.5
}

// With the paper's constants the allowance shrinks with size: small components merge freely,
// large ones only when their union stays as uniform as they are.
TEST(Segmentation, PaperConstantsAllowanceShrinksWithSize) {
  const SegmentationOptions p;
  EXPECT_TRUE(try_union(ComponentStats::pixel(0.0f, 0.5f), ComponentStats::pixel(0.5f, 0.6f), p.k_theta, p.k_mag));
  // 500 + 500 pixels: K_D / 1000 = 0.1 rad, so 0.05 + 0.1 < 0.35 = D(u).
  EXPECT_FALSE(try_union(stats(500, 0.0f, 0.05f, 0.5f, 0.5f), stats(500, 0.30f, 0.35f, 0.5f, 0.5f), p.k_theta,
                         p.k_mag));
  EXPECT_TRUE(try_union(stats(500, 0.0f, 0.05f, 0.5f, 0.5f), stats(500, 0.05f, 0.10f, 0.5f, 0.5f), p.k_theta,
                        p.k_mag));
}

// Directions just below +pi and just above -pi are 0.07 rad apart, not 6.2: they merge, and the
// stored union is the short interval through pi with its centre in (-pi, pi].
TEST(Segmentation, MergeRuleHandlesThePiWrapAround) {
  const ComponentStats n = stats(5, 3.10f, 3.12f, 0.5f, 0.5f);
  const ComponentStats m = stats(5, -3.13f, -3.11f, 0.5f, 0.5f);
  const float expected_range = (2 * kPi - 3.11f) - 3.10f;  // 0.073
  for (const auto& [a, b] : {std::pair{n, m}, std::pair{m, n}}) {
    // K_D / 10 = 0.1: the wrapped range 0.073 passes, the naive 6.25 could not.
    const auto u = try_union(a, b, 1.0, 1.0);
    ASSERT_TRUE(u);
    EXPECT_NEAR(u->theta_range(), expected_range, 1e-5);
    const float centre = 0.5f * (u->theta_min + u->theta_max);
    EXPECT_GT(centre, -kPi);
    EXPECT_LE(centre, kPi);
    EXPECT_NEAR(u->theta_min, 3.10f, 1e-5);  // the interval [3.10, 3.173] in either argument order
  }
  // A union whose centre falls beyond +pi ([3.12, 3.19]) is stored one turn lower, in either order.
  const ComponentStats p = stats(5, 3.12f, 3.14f, 0.5f, 0.5f);
  const ComponentStats q = stats(5, -3.10f, -3.09f, 0.5f, 0.5f);
  for (const auto& [a, b] : {std::pair{p, q}, std::pair{q, p}}) {
    const auto u = try_union(a, b, 1.0, 1.0);
    ASSERT_TRUE(u);
    EXPECT_NEAR(u->theta_min, 3.12f - 2 * kPi, 1e-5);
    EXPECT_NEAR(u->theta_max, -3.09f, 1e-5);
  }
  // A third component at -3.0 rad: 0.17 rad from the union's lower end through the wrap.
  const auto u = *try_union(n, m, 1.0, 1.0);
  const auto w = try_union(u, stats(5, -3.0f, -3.0f, 0.5f, 0.5f), 10.0, 1.0);
  ASSERT_TRUE(w);
  EXPECT_NEAR(w->theta_range(), (2 * kPi - 3.0f) - 3.10f, 1e-5);
}

// A straight edge whose gradient points along -x has directions on both sides of +-pi (noise
// flips the sign of Iy). Without the wrap handling it would split into a +pi and a -pi half.
TEST(Segmentation, EdgeFacingMinusXStaysOneCluster) {
  ImageF img(40, 40);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) img.at(x, y) = x < 20 ? 0.9f : 0.1f;  // light left, dark right
  synth::add_gaussian_noise(img, 0.01, 3);
  const Gradients g = compute_gradients(gaussian_blur(img, kSegSigma));
  const Clusters c = segment_clusters(g);
  ASSERT_GE(c.size(), 1u);
  std::size_t biggest = 0;
  for (std::size_t i = 1; i < c.size(); ++i)
    if (c[i].size() > c[biggest].size()) biggest = i;
  int positive = 0, negative = 0;
  for (const ClusterPixel& p : c[biggest]) {
    EXPECT_GT(std::abs(p.theta), 2.8f);  // all pointing (roughly) to -x
    (p.theta > 0 ? positive : negative)++;
  }
  EXPECT_GT(positive, 20);
  EXPECT_GT(negative, 20);
  // The edge band (4 columns wide, 38 rows between the zero borders) is almost entirely one cluster.
  EXPECT_GE(c[biggest].size(), 0.9 * 4 * 38);
}

TEST(Segmentation, DarkSquareGivesFourLargeClustersOnePerSide) {
  const auto corners = synth::square_corners_ccw({60.3, 58.7}, 25.0, 20 * std::numbers::pi / 180);
  const ImageF img =
      synth::render_convex_polygon(120, 120, {corners.begin(), corners.end()}, 0.2f, 0.8f);
  const Gradients g = compute_gradients(gaussian_blur(img, kSegSigma));
  const SegmentationOptions opt;
  const Clusters c = segment_clusters(g, opt);

  // Every reported pixel is active, reported once, in a cluster of at least min_cluster_size.
  std::set<std::pair<int, int>> seen;
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_GE(c[i].size(), static_cast<std::size_t>(opt.min_cluster_size));
    for (const ClusterPixel& p : c[i]) {
      EXPECT_GT(p.mag, opt.min_mag);
      EXPECT_EQ(p.mag, g.mag[static_cast<std::size_t>(p.y * g.width + p.x)]);
      EXPECT_TRUE(seen.insert({p.x, p.y}).second);
    }
  }

  // The four sides: outward normals (the gradient points to the light outside) at phi + k pi/2.
  const double phi = 20 * std::numbers::pi / 180;
  std::vector<int> side_cluster(4, -1);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i].size() < 100) continue;  // a side is ~50 px long and ~4 px wide
    double sx = 0, sy = 0;
    for (const ClusterPixel& p : c[i]) {
      sx += std::cos(p.theta);
      sy += std::sin(p.theta);
    }
    const double mean = std::atan2(sy, sx);
    int side = -1;
    for (int k = 0; k < 4; ++k) {
      const double normal = phi + k * std::numbers::pi / 2 - std::numbers::pi / 2;  // -y side first
      if (angle_distance(static_cast<float>(mean), static_cast<float>(normal)) < 0.05f) side = k;
    }
    ASSERT_GE(side, 0) << "large cluster with mean direction " << mean;
    EXPECT_EQ(side_cluster[side], -1) << "two large clusters on one side";
    side_cluster[side] = static_cast<int>(i);
    float lo = 10, hi = -10;
    for (const ClusterPixel& p : c[i]) {
      const float d = static_cast<float>(p.theta - mean);
      const float wrapped = std::remainder(d, 2 * kPi);
      lo = std::min(lo, wrapped);
      hi = std::max(hi, wrapped);
    }
    EXPECT_LT(hi - lo, 0.6f) << "side cluster spans too many directions";
  }
  for (int k = 0; k < 4; ++k) EXPECT_GE(side_cluster[k], 0) << "no cluster for side " << k;
}

TEST(Segmentation, OutputIsDeterministicAndInRasterOrder) {
  ImageF img(80, 60, 0.5f);
  synth::add_gaussian_noise(img, 0.08, 11);
  const Gradients g = compute_gradients(gaussian_blur(img, kSegSigma));
  const Clusters a = segment_clusters(g);
  const Clusters b = segment_clusters(g);
  ASSERT_GT(a.size(), 3u);
  ASSERT_EQ(a.offsets, b.offsets);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    ASSERT_EQ(a.pixels[i].x, b.pixels[i].x);
    ASSERT_EQ(a.pixels[i].y, b.pixels[i].y);
  }
  auto raster = [&](const ClusterPixel& p) { return p.y * g.width + p.x; };
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = 1; j < a[i].size(); ++j) EXPECT_LT(raster(a[i][j - 1]), raster(a[i][j]));
    if (i > 0) {
      EXPECT_LT(raster(a[i - 1][0]), raster(a[i][0]));
    }
  }
}

TEST(Segmentation, FlatOrEmptyImagesHaveNoClusters) {
  EXPECT_EQ(segment_image(ImageF(30, 20, 0.4f)).size(), 0u);
  EXPECT_EQ(segment_clusters(Gradients{}).size(), 0u);
}

}  // namespace test_segmentation
