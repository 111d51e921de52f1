#pragma once
// Graph-based clustering of edge pixels (paper section III-A, after Felzenszwalb; constants:
// docs/paper-to-code.md section 1).
//
// Conventions: input is compute_gradients() output (squared magnitude, theta in (-pi, pi]),
// x right, y down, pixel centres at integer coordinates; pixel index i = y * width + x.
//
// The graph: a node per pixel; each pixel (x, y) gets up to 4 edges, to (x+1, y), (x, y+1),
// (x+1, y+1) and (x-1, y+1) (so every 8-neighbour pair is visited once), and only when both
// pixels have mag > min_mag and their direction difference, wrapped into [0, pi], is at most
// max_edge_cost. The edge weight is that difference in fixed point,
// (int)(dtheta / max_edge_cost * weight_scale) in 0..weight_scale, so a counting sort orders
// the edges in linear time.
//
// Edges are processed by increasing weight (stable: ties in generation order, i.e. raster order
// of the first pixel, then the neighbour order above). Components live in a union-find forest
// (path compression + union by size) whose roots store the component's size and its direction
// and magnitude bounds. For an edge joining distinct components n and m the paper's tests are
//   (1) D(n u m) <= min(D(n), D(m)) + K_D / |n u m|     D = max theta - min theta (radians)
//   (2) M(n u m) <= min(M(n), M(m)) + K_M / |n u m|     M = max mag - min mag
// and the components are joined only when both hold.
//
// 2 pi wrap-around: a component's direction range is stored as an interval [theta_min, theta_max]
// on the real line whose centre is kept in (-pi, pi] (the ends may stick out of it). To unite
// two ranges, m's interval is shifted by the multiple of 2 pi (-2 pi, 0 or +2 pi) that brings its
// centre nearest to n's centre, then min/max are taken, and the result is shifted back so its
// centre is in (-pi, pi]. This is exact as long as ranges stay well below pi, which is what
// useful edges have (paper: "useful edges will have a span of much less than pi").
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "gradient.hpp"

namespace tagbench {

struct SegmentationOptions {
  float min_mag = 0.004f;                                // minMag: on the SQUARED magnitude, image in [0, 1]
  double max_edge_cost = 30.0 * std::numbers::pi / 180;  // maxEdgeCost (radians): larger dtheta, no edge
  int weight_scale = 100;                                // edge weights are 0..weight_scale
  double k_theta = 100.0;                                // K_D (thetaThresh) of test (1), radians
  double k_mag = 1200.0;                                 // K_M (magThresh) of test (2)
  int min_cluster_size = 4;                              // smaller components are not reported
};

// An edge between pixels a and b (pixel indices) with its fixed-point weight.
struct GraphEdge {
  std::uint32_t a = 0;
  std::uint32_t b = 0;
  std::uint32_t weight = 0;
};

// |a - b| wrapped into [0, pi]; a and b in radians (any range within a few turns).
float angle_distance(float a, float b);

// The graph described above, in generation order (unsorted).
std::vector<GraphEdge> build_edges(const Gradients& g, const SegmentationOptions& opt = {});

// Stable counting sort by weight, O(edges + max_weight). Every weight must be <= max_weight
// (throws std::invalid_argument otherwise).
std::vector<GraphEdge> counting_sort_edges(const std::vector<GraphEdge>& edges, int max_weight);

// What a union-find root knows about its component.
struct ComponentStats {
  std::uint32_t size = 1;
  float theta_min = 0.0f, theta_max = 0.0f;  // see "2 pi wrap-around" above
  float mag_min = 0.0f, mag_max = 0.0f;

  static ComponentStats pixel(float theta, float mag) { return {1, theta, theta, mag, mag}; }
  float theta_range() const { return theta_max - theta_min; }  // D()
  float mag_range() const { return mag_max - mag_min; }        // M()
};

// The merge rule: the statistics of n u m when tests (1) and (2) both pass, nullopt otherwise.
std::optional<ComponentStats> try_union(const ComponentStats& n, const ComponentStats& m, double k_theta,
                                        double k_mag);

struct ClusterPixel {
  int x = 0, y = 0;
  float mag = 0.0f;    // squared gradient magnitude
  float theta = 0.0f;  // gradient direction in (-pi, pi]
};

// All clusters in one flat array (one allocation per frame, not one per cluster).
// Cluster i is pixels[offsets[i], offsets[i+1]). Clusters are ordered by their first pixel in
// raster order, and each cluster's pixels are in raster order, so the output is deterministic.
struct Clusters {
  std::vector<ClusterPixel> pixels;
  std::vector<std::size_t> offsets{0};  // size() + 1 entries

  std::size_t size() const { return offsets.size() - 1; }
  std::span<const ClusterPixel> operator[](std::size_t i) const {
    return {pixels.data() + offsets[i], offsets[i + 1] - offsets[i]};
  }
};

// The whole stage: graph, sort, merge, then every component of at least min_cluster_size pixels
// (only pixels with mag > min_mag are ever reported).
Clusters segment_clusters(const Gradients& g, const SegmentationOptions& opt = {});

// The stage's working storage, kept between frames by the detector's workspace (detector.hpp) so
// frames of one size are segmented without reallocating. Contents are scratch: only the capacities
// carry over from one call to the next.
struct SegmentationScratch {
  std::vector<GraphEdge> edges, sorted;        // content-dependent: up to 4 per active pixel
  std::vector<std::size_t> weight_start;       // counting sort histogram, weight_scale + 1
  std::vector<std::uint32_t> parent;           // union-find, a node per pixel
  std::vector<ComponentStats> stats;           // a node per pixel
  std::vector<std::int32_t> cluster_of;        // a node per pixel
  std::vector<std::size_t> count, fill;        // per reported cluster
};

// segment_clusters() with caller-owned storage; `out` is overwritten. Same result.
void segment_clusters(const Gradients& g, const SegmentationOptions& opt, SegmentationScratch& scratch,
                      Clusters& out);

}  // namespace tagbench
