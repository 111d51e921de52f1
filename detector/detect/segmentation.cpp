#include "detect/segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tagbench {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Root of x, pointing every node on the way directly at the root (path compression).
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  std::uint32_t r = x;
  while (parent[r] != r) r = parent[r];
  while (parent[x] != r) {
    const std::uint32_t next = parent[x];
    parent[x] = r;
    x = next;
  }
  return r;
}

}  // namespace

float angle_distance(float a, float b) {
  float d = std::fabs(a - b);
  if (d > kTwoPi) d = std::fmod(d, kTwoPi);  // never taken for two angles in (-pi, pi]
  return d > kPi ? kTwoPi - d : d;
}

namespace {

// build_edges into `edges` (cleared). The reservation has a quarter of headroom over the worst case
// of this frame, so a reused vector takes the next frames of a similar scene without reallocating
// (the headroom costs address space only: pages never written are never resident).
void build_edges_into(const Gradients& g, const SegmentationOptions& opt, std::vector<GraphEdge>& edges) {
  const int w = g.width, h = g.height;
  const float min_mag = opt.min_mag;
  const float max_cost = static_cast<float>(opt.max_edge_cost);
  const float to_weight = static_cast<float>(opt.weight_scale / opt.max_edge_cost);
  const auto max_weight = static_cast<std::uint32_t>(opt.weight_scale);

  // Reserve for the worst case of the active pixels (4 edges each) so the push_backs never reallocate.
  std::size_t active = 0;
  for (const float m : g.mag) active += m > min_mag;
  edges.clear();
  if (edges.capacity() < 4 * active) edges.reserve(5 * active);

  auto try_edge = [&](std::uint32_t a, std::uint32_t b) {
    if (!(g.mag[b] > min_mag)) return;
    const float d = angle_distance(g.theta[a], g.theta[b]);
    if (!(d <= max_cost)) return;
    // min() guards the float rounding of d == max_cost against a weight above the scale.
    edges.push_back({a, b, std::min(max_weight, static_cast<std::uint32_t>(d * to_weight))});
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const auto i = static_cast<std::uint32_t>(y * w + x);
      if (!(g.mag[i] > min_mag)) continue;
      if (x + 1 < w) try_edge(i, i + 1);
      if (y + 1 < h) {
        const auto below = i + static_cast<std::uint32_t>(w);
        try_edge(i, below);
        if (x + 1 < w) try_edge(i, below + 1);
        if (x > 0) try_edge(i, below - 1);
      }
    }
  }
}

// counting_sort_edges into `sorted`, with `start` as the histogram's storage.
void counting_sort_into(const std::vector<GraphEdge>& edges, int max_weight, std::vector<std::size_t>& start,
                        std::vector<GraphEdge>& sorted) {
  if (max_weight < 0) throw std::invalid_argument("counting_sort_edges: negative max_weight");
  start.assign(static_cast<std::size_t>(max_weight) + 1, 0);
  for (const GraphEdge& e : edges) {
    if (e.weight > static_cast<std::uint32_t>(max_weight))
      throw std::invalid_argument("counting_sort_edges: weight " + std::to_string(e.weight) + " > " +
                                  std::to_string(max_weight));
    ++start[e.weight];
  }
  // Histogram -> first output slot of each weight; filling in input order keeps the sort stable.
  std::size_t sum = 0;
  for (std::size_t& s : start) {
    const std::size_t c = s;
    s = sum;
    sum += c;
  }
  if (sorted.capacity() < edges.size())  // a reused vector gets headroom like build_edges_into's
    sorted.reserve(edges.size() + edges.size() / 4);
  sorted.resize(edges.size());
  for (const GraphEdge& e : edges) sorted[start[e.weight]++] = e;
}

}  // namespace

std::vector<GraphEdge> build_edges(const Gradients& g, const SegmentationOptions& opt) {
  std::vector<GraphEdge> edges;
  build_edges_into(g, opt, edges);
  return edges;
}

std::vector<GraphEdge> counting_sort_edges(const std::vector<GraphEdge>& edges, int max_weight) {
  std::vector<std::size_t> start;
  std::vector<GraphEdge> sorted;
  counting_sort_into(edges, max_weight, start, sorted);
  return sorted;
}

std::optional<ComponentStats> try_union(const ComponentStats& n, const ComponentStats& m, double k_theta,
                                        double k_mag) {
  const std::uint32_t size = n.size + m.size;

  // Bring m's direction interval to the turn nearest n's (both centres are in (-pi, pi]).
  const float cn = 0.5f * (n.theta_min + n.theta_max);
  const float cm = 0.5f * (m.theta_min + m.theta_max);
  float shift = 0.0f;
  if (cn - cm > kPi)
    shift = kTwoPi;
  else if (cn - cm < -kPi)
    shift = -kTwoPi;
  float tmin = std::min(n.theta_min, m.theta_min + shift);
  float tmax = std::max(n.theta_max, m.theta_max + shift);

  const float d = tmax - tmin;
  if (!(d <= std::min(n.theta_range(), m.theta_range()) + static_cast<float>(k_theta / size))) return std::nullopt;
  const float mmin = std::min(n.mag_min, m.mag_min);
  const float mmax = std::max(n.mag_max, m.mag_max);
  if (!(mmax - mmin <= std::min(n.mag_range(), m.mag_range()) + static_cast<float>(k_mag / size)))
    return std::nullopt;

  // Keep the stored centre in (-pi, pi] so the stored values stay bounded however long the merging goes.
  const float c = 0.5f * (tmin + tmax);
  if (c > kPi) {
    tmin -= kTwoPi;
    tmax -= kTwoPi;
  } else if (c <= -kPi) {
    tmin += kTwoPi;
    tmax += kTwoPi;
  }
  return ComponentStats{size, tmin, tmax, mmin, mmax};
}

Clusters segment_clusters(const Gradients& g, const SegmentationOptions& opt) {
  SegmentationScratch scratch;
  Clusters out;
  segment_clusters(g, opt, scratch, out);
  return out;
}

void segment_clusters(const Gradients& g, const SegmentationOptions& opt, SegmentationScratch& scratch,
                      Clusters& out) {
  out.pixels.clear();
  out.offsets.assign(1, 0);
  const std::size_t n = g.mag.size();
  if (n == 0) return;
  build_edges_into(g, opt, scratch.edges);
  counting_sort_into(scratch.edges, opt.weight_scale, scratch.weight_start, scratch.sorted);
  const std::vector<GraphEdge>& edges = scratch.sorted;

  // Union-find; stats[r] is valid for roots r only. Every entry is set below, so resize() suffices.
  std::vector<std::uint32_t>& parent = scratch.parent;
  std::vector<ComponentStats>& stats = scratch.stats;
  parent.resize(n);
  stats.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    parent[i] = static_cast<std::uint32_t>(i);
    stats[i] = ComponentStats::pixel(g.theta[i], g.mag[i]);
  }
  for (const GraphEdge& e : edges) {
    std::uint32_t ra = find_root(parent, e.a);
    std::uint32_t rb = find_root(parent, e.b);
    if (ra == rb) continue;
    const std::optional<ComponentStats> u = try_union(stats[ra], stats[rb], opt.k_theta, opt.k_mag);
    if (!u) continue;
    if (stats[ra].size < stats[rb].size) std::swap(ra, rb);  // union by size: ra is the bigger
    parent[rb] = ra;
    stats[ra] = *u;
  }

  // Number the reported components in raster order of their first pixel and count their pixels.
  // (Pixels at or below min_mag have no edges, so only active pixels can be in a big component;
  // the explicit test keeps them out even when min_cluster_size <= 1.)
  const auto min_size = static_cast<std::uint32_t>(std::max(1, opt.min_cluster_size));
  std::vector<std::int32_t>& cluster_of = scratch.cluster_of;  // indexed by root
  cluster_of.assign(n, -1);
  std::vector<std::size_t>& count = scratch.count;
  count.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (!(g.mag[i] > opt.min_mag)) continue;
    const std::uint32_t r = find_root(parent, static_cast<std::uint32_t>(i));
    if (stats[r].size < min_size) continue;
    if (cluster_of[r] < 0) {
      cluster_of[r] = static_cast<std::int32_t>(count.size());
      count.push_back(0);
    }
    ++count[static_cast<std::size_t>(cluster_of[r])];
  }
  out.offsets.assign(count.size() + 1, 0);
  for (std::size_t c = 0; c < count.size(); ++c) out.offsets[c + 1] = out.offsets[c] + count[c];
  out.pixels.resize(out.offsets.back());
  std::vector<std::size_t>& fill = scratch.fill;
  fill.assign(out.offsets.begin(), out.offsets.end() - 1);
  const int w = g.width;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(g.mag[i] > opt.min_mag)) continue;
    const std::int32_t c = cluster_of[parent[i]];  // paths are fully compressed by the loop above
    if (c < 0) continue;
    const int x = static_cast<int>(i % static_cast<std::size_t>(w));
    const int y = static_cast<int>(i / static_cast<std::size_t>(w));
    out.pixels[fill[static_cast<std::size_t>(c)]++] = {x, y, g.mag[i], g.theta[i]};
  }
}

}  // namespace tagbench
