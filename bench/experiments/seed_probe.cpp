// Seed probes for tags without a candidate quad (seed_probe.hpp).
#include "seed_probe.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include "detect/decode_quads.hpp"
#include "detect/edge_refine.hpp"
#include "detect/homography.hpp"

namespace tagbench::bench {

namespace {

// The quad `corners` decoded as the profile decodes (its readers, bits corrected by family, soft decoding).
std::optional<Detection> decode_at(const ImageF& img, const Corners& corners, const TagFamily& family,
                                   const DetectorOptions& opt) {
  Quad q;
  q.corners = corners;
  auto found = decode_quads(img, std::span(&q, 1), std::span(&family, 1), opt.max_hamming, opt.payload,
                            &opt.payload_area, nullptr, nullptr, opt.hamming_by_family, &opt.soft_decode);
  if (found.size() != 1) return std::nullopt;
  return found[0];
}

// The same after the threshold stage's edge refinement (kept as given where it is rejected).
std::optional<Detection> refine_and_decode(const ImageF& img, Corners corners, const TagFamily& family,
                                           const DetectorOptions& opt) {
  EdgeRefineScratch rs;
  if (const auto r = refine_quad_edges(img, corners, opt.threshold_quads.refine, rs)) corners = *r;
  return decode_at(img, corners, family, opt);
}


bool refines_and_decodes(const ImageF& img, const Corners& corners, int id, const TagFamily& family,
                         const DetectorOptions& opt) {
  const auto d = refine_and_decode(img, corners, family, opt);
  return d && d->id == id;
}

// The dominant direction of the gradients mod 90 degrees in the box of half-width r around c (radians):
// angles times four, weighted by the squared magnitude, so a square's four sides agree.
double dominant_turn(const ImageF& img, const Eigen::Vector2d& c, int r) {
  double c4 = 0, s4 = 0;
  for (int y = static_cast<int>(c.y()) - r; y <= static_cast<int>(c.y()) + r; ++y)
    for (int x = static_cast<int>(c.x()) - r; x <= static_cast<int>(c.x()) + r; ++x) {
      if (x < 1 || y < 1 || x >= img.width - 1 || y >= img.height - 1) continue;
      const double gx = img.at(x + 1, y) - img.at(x - 1, y), gy = img.at(x, y + 1) - img.at(x, y - 1);
      const double m2 = gx * gx + gy * gy, a = std::atan2(gy, gx);
      c4 += m2 * std::cos(4 * a), s4 += m2 * std::sin(4 * a);
    }
  return std::atan2(s4, c4) / 4;
}

Corners turned_square(const Eigen::Vector2d& centre, double half, double turn) {
  const double c = std::cos(turn), s = std::sin(turn);
  Corners q;
  const double u[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i)
    q[i] = centre + half * Eigen::Vector2d(c * u[i][0] - s * u[i][1], s * u[i][0] + c * u[i][1]);
  return q;
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain; counter-clockwise in (x right, y up) terms.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

double area(const Corners& c) {
  double a = 0;
  for (int i = 0; i < 4; ++i) a += c[i].x() * c[(i + 1) % 4].y() - c[(i + 1) % 4].x() * c[i].y();
  return a / 2;
}

// The quad through tag coordinates (u, v) = (+-scale, +-scale) of `q`'s homography.
std::optional<Corners> scaled(const Corners& q, double scale) {
  const auto H = tag_homography(q);
  if (!H) return std::nullopt;
  Corners s;
  const double u[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d v = *H * Eigen::Vector3d(scale * u[i][0], scale * u[i][1], 1);
    s[i] = v.head<2>() / v.z();
  }
  return s;
}

// The largest-area quadrilateral on the hull's vertices (O(n^3): a diagonal i-k, the best vertex
// on either chain between them).
Corners largest_quad(const std::vector<Eigen::Vector2d>& h) {
  const std::size_t n = h.size();
  Corners best{};
  double best_a = -1;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = i + 2; k < n; ++k) {
      double a1 = -1, a2 = -1;
      std::size_t j1 = i, j2 = k;
      for (std::size_t j = i + 1; j < k; ++j)
        if (const double a = std::abs(cross(h[i], h[j], h[k])); a > a1) a1 = a, j1 = j;
      for (std::size_t j = k + 1; j < n + i; ++j)
        if (const double a = std::abs(cross(h[k], h[j % n], h[i])); a > a2) a2 = a, j2 = j % n;
      if (a1 < 0 || a2 < 0) continue;
      if (a1 + a2 > best_a) best_a = a1 + a2, best = {h[i], h[j1], h[k], h[j2]};
    }
  if (area(best) < 0) std::swap(best[1], best[3]);  // clockwise on screen (y down): TL, TR, BR, BL order
  return best;
}

}  // namespace

Eigen::Vector2d centre_of(const Corners& c) { return (c[0] + c[1] + c[2] + c[3]) / 4; }

bool inside_any(std::span<const Corners> quads, const Eigen::Vector2d& p) {
  for (const Corners& q : quads) {
    int pos = 0, neg = 0;  // p strictly on the inner side of all four edges, either winding
    for (int i = 0; i < 4; ++i) {
      const double c = cross(q[i], q[(i + 1) % 4], p);
      pos += c > 0, neg += c < 0;
    }
    if (pos == 4 || neg == 4) return true;
  }
  return false;
}

double best_corner_match(const Corners& a, const Corners& b) {
  double best = HUGE_VAL;
  for (int s = 0; s < 4; ++s) best = std::min(best, max_corner_distance(a, b, s));
  return best;
}

int payload_hull_decodes(const ImageF& img, const BoundaryGroups& groups, const Corners& truth, int id,
                         const TagFamily& family, const DetectorOptions& opt) {
  const Eigen::Vector2d centre = centre_of(truth);
  const double size = std::sqrt(std::abs(area(truth)));
  std::vector<Eigen::Vector2d> p;
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const auto pts = groups.group(g);
    const DoubledBox b = bounding_box(pts);
    const double w = (b.xmax - b.xmin) / 2.0, h = (b.ymax - b.ymin) / 2.0;
    const Eigen::Vector2d c((b.xmin + b.xmax) / 4.0, (b.ymin + b.ymax) / 4.0);
    if (std::max(w, h) > 0.8 * size || (c - centre).norm() > 0.45 * size) continue;
    for (const auto& q : pts) p.emplace_back(q.x2 / 2.0, q.y2 / 2.0);
  }
  const auto hull = convex_hull(std::move(p));
  if (hull.size() < 4) return 0;
  const Corners q = largest_quad(hull);
  if (std::getenv("SEED_DEBUG")) {
    const auto s = scaled(q, 8.0 / 6);
    const double best = s ? best_corner_match(*s, truth) : HUGE_VAL;
    std::fprintf(stdout, "  payload hull %zu vertices, scaled quad off %.1f\n", hull.size(), best);
  }
  for (const double k : {8.0 / 6, 8.0 / 6.5, 8.0 / 5.5})
    if (const auto s = scaled(q, k); s && refines_and_decodes(img, *s, id, family, opt)) return 1;
  return 0;
}

int centre_scale_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                         const DetectorOptions& opt, double angle_step_deg) {
  const Eigen::Vector2d centre = centre_of(truth);
  const double half = 0.5 * std::sqrt(std::abs(area(truth)));
  int ok = 0;
  for (double a = 0; a < 90; a += angle_step_deg)
    ok += refines_and_decodes(img, turned_square(centre, half, a * M_PI / 180), id, family, opt);
  return ok;
}

int centre_scale_turn_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                              const DetectorOptions& opt, double& turn_deg) {
  const Eigen::Vector2d centre = centre_of(truth);
  const double half = 0.5 * std::sqrt(std::abs(area(truth)));
  const double turn = dominant_turn(img, centre, static_cast<int>(std::ceil(1.25 * half)));
  turn_deg = turn * 180 / M_PI;
  int ok = 0;
  for (const double k : {0.9, 1.0, 1.1}) ok += refines_and_decodes(img, turned_square(centre, k * half, turn), id, family, opt);
  return ok;
}

std::vector<BlobSeed> blob_seeds(const ImageF& img, std::span<const double> sides, double min_response,
                                 std::span<const Corners> covered, int max_seeds) {
  const int w = img.width, h = img.height;
  std::vector<double> sum(static_cast<std::size_t>(w + 1) * (h + 1), 0.0);  // integral image
  for (int y = 0; y < h; ++y) {
    double row = 0;
    for (int x = 0; x < w; ++x) {
      row += img.at(x, y);
      sum[static_cast<std::size_t>(y + 1) * (w + 1) + x + 1] = sum[static_cast<std::size_t>(y) * (w + 1) + x + 1] + row;
    }
  }
  const auto box = [&](int x0, int y0, int x1, int y1) {  // inclusive pixel box
    const auto at = [&](int x, int y) { return sum[static_cast<std::size_t>(y) * (w + 1) + x]; };
    return at(x1 + 1, y1 + 1) - at(x0, y1 + 1) - at(x1 + 1, y0) + at(x0, y0);
  };
  const int step = 2;
  const int gw = w / step, gh = h / step;
  std::vector<BlobSeed> found;
  std::vector<float> resp(static_cast<std::size_t>(gw) * gh);
  for (const double side : sides) {
    const int ri = static_cast<int>(std::lround(0.45 * side)), ro = static_cast<int>(std::lround(0.65 * side));
    const double ni = (2.0 * ri + 1) * (2 * ri + 1), no = (2.0 * ro + 1) * (2 * ro + 1);
    std::fill(resp.begin(), resp.end(), 0.0f);
    for (int gy = 0; gy < gh; ++gy)
      for (int gx = 0; gx < gw; ++gx) {
        const int x = gx * step, y = gy * step;
        if (x - ro < 0 || y - ro < 0 || x + ro >= w || y + ro >= h) continue;
        const double in = box(x - ri, y - ri, x + ri, y + ri), out = box(x - ro, y - ro, x + ro, y + ro);
        resp[static_cast<std::size_t>(gy) * gw + gx] = static_cast<float>((out - in) / (no - ni) - in / ni);
      }
    for (int gy = 1; gy + 1 < gh; ++gy)
      for (int gx = 1; gx + 1 < gw; ++gx) {
        const float v = resp[static_cast<std::size_t>(gy) * gw + gx];
        if (v < min_response) continue;
        bool peak = true;
        for (int dy = -1; dy <= 1 && peak; ++dy)
          for (int dx = -1; dx <= 1 && peak; ++dx)
            if ((dx || dy) && resp[static_cast<std::size_t>(gy + dy) * gw + gx + dx] > v) peak = false;
        if (peak) found.push_back({Eigen::Vector2d(gx * step, gy * step), side, v});
      }
  }
  std::sort(found.begin(), found.end(), [](const BlobSeed& a, const BlobSeed& b) { return a.response > b.response; });
  std::vector<BlobSeed> kept;
  for (const BlobSeed& s : found) {
    bool skip = false;
    for (const BlobSeed& k : kept) skip |= (k.centre - s.centre).norm() < 0.5 * std::max(k.side, s.side);
    skip |= inside_any(covered, s.centre);
    if (!skip) kept.push_back(s);
    if (static_cast<int>(kept.size()) >= max_seeds) break;
  }
  return kept;
}

std::optional<Detection> decode_seed(const ImageF& img, const BlobSeed& seed, const TagFamily& family,
                                     const DetectorOptions& opt, std::span<const double> side_factors) {
  const double half = 0.5 * seed.side;
  const double turn = dominant_turn(img, seed.centre, static_cast<int>(std::ceil(1.25 * half)));
  for (const double k : side_factors)
    if (auto d = refine_and_decode(img, turned_square(seed.centre, k * half, turn), family, opt)) return d;
  return std::nullopt;
}

int jitter_decodes(const ImageF& img, const Corners& quad, int id, const TagFamily& family, const DetectorOptions& opt,
                   double step_px, bool refine) {
  int ok = 0;
  const double d[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (int c = 0; c < 4; ++c)
    for (const auto& v : d) {
      Corners q = quad;
      q[c] += step_px * Eigen::Vector2d(v[0], v[1]);
      const auto f = refine ? refine_and_decode(img, q, family, opt) : decode_at(img, q, family, opt);
      ok += f && f->id == id;
    }
  return ok;
}

int perturbed_truth_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                            const DetectorOptions& opt, double shift_px, int trials, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  int ok = 0;
  for (int k = 0; k < trials; ++k) {
    Corners c = truth;
    for (auto& p : c) {
      const double a = angle(rng);
      p += shift_px * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    ok += refines_and_decodes(img, c, id, family, opt);
  }
  return ok;
}

bool hull_seed_decodes(const ImageF& img, const BoundaryGroups& groups, const Corners& truth, int id,
                       const TagFamily& family, const DetectorOptions& opt, int& groups_near, bool& shrunk) {
  shrunk = false;
  const Eigen::Vector2d centre = centre_of(truth);
  const double size = std::sqrt(std::abs(area(truth)));
  groups_near = 0;
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const auto pts = groups.group(g);
    if (pts.size() < 8) continue;
    const DoubledBox b = bounding_box(pts);
    const double w = (b.xmax - b.xmin) / 2.0, h = (b.ymax - b.ymin) / 2.0;
    const Eigen::Vector2d c((b.xmin + b.xmax) / 4.0, (b.ymin + b.ymax) / 4.0);
    if (std::max(w, h) < 0.5 * size || std::max(w, h) > 1.6 * size || (c - centre).norm() > 0.5 * size) continue;
    ++groups_near;
    std::vector<Eigen::Vector2d> p;
    p.reserve(pts.size());
    for (const auto& q : pts) p.emplace_back(q.x2 / 2.0, q.y2 / 2.0);
    const auto hull = convex_hull(std::move(p));
    if (hull.size() < 4) continue;
    const Corners q = largest_quad(hull);
    if (std::getenv("SEED_DEBUG")) {
      const double best = best_corner_match(q, truth);
      std::fprintf(stdout, "  group %zu: %zu pts box %.1f x %.1f (tag %.1f) centre off %.1f hull %zu quad off %.1f\n", g,
                   pts.size(), w, h, size, (c - centre).norm(), hull.size(), best);
    }
    if (refines_and_decodes(img, q, id, family, opt)) return true;
    // The group may outline the black square with its white ring classed dark too (10 cells across
    // for 8): the quad shrunk by 8/10 about its centre, through its homography.
    if (const auto s = scaled(q, 0.8); s && refines_and_decodes(img, *s, id, family, opt)) {
      shrunk = true;
      return true;
    }
  }
  return false;
}

}  // namespace tagbench::bench
