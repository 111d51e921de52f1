#include "detect/quad_fit_occluded.hpp"

#include "detect/angle_order.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace tagbench {
namespace {

struct RunMoments {
  double x = 0, y = 0, xx = 0, xy = 0, yy = 0, n = 0;
  void add(double px, double py) { x += px, y += py, xx += px * px, xy += px * py, yy += py * py, n += 1; }
  void add(const RunMoments& o) { x += o.x, y += o.y, xx += o.xx, xy += o.xy, yy += o.yy, n += o.n; }
};

struct RunLine {
  double cx = 0, cy = 0, nx = 0, ny = 0, mse = 0;  // centroid, unit normal, mean squared distance
  RunMoments m;
  int count = 0;
};

RunLine fit(const RunMoments& m) {
  RunLine l;
  l.m = m;
  l.count = static_cast<int>(m.n);
  l.cx = m.x / m.n, l.cy = m.y / m.n;
  const double cxx = m.xx / m.n - l.cx * l.cx, cxy = m.xy / m.n - l.cx * l.cy, cyy = m.yy / m.n - l.cy * l.cy;
  const double root = std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy);
  l.mse = std::max(0.0, 0.5 * (cxx + cyy - root));
  const double big = 0.5 * (cxx + cyy + root);
  const double ax = cxx - big, ay = cxy, bx = cxy, by = cyy - big;  // rows of (C - big I): normal to the line
  const double la = ax * ax + ay * ay, lb = bx * bx + by * by;
  const double len = std::sqrt(std::max(la, lb));
  if (len > 1e-12) l.nx = (la > lb ? ax : bx) / len, l.ny = (la > lb ? ay : by) / len;
  return l;
}

double distance(const RunLine& l, double x, double y) { return l.nx * (x - l.cx) + l.ny * (y - l.cy); }

// Douglas-Peucker over the cyclic sequence: vertex indices, increasing. False, with the split
// abandoned, once there are more than `max_vertices` (no vertex is ever removed again, so the caller
// would reject the outline: textures split into hundreds of runs, and this is where their cost was).
bool split_runs(OccludedQuadFitScratch& s, double tol, int max_vertices) {
  const int n = static_cast<int>(s.pts.size());
  const auto& p = s.pts;
  int a = 0;
  double cx = 0, cy = 0;
  for (const auto& q : p) cx += q.x, cy += q.y;
  cx /= n, cy /= n;
  double best = -1;
  for (int i = 0; i < n; ++i) {
    const double d = (p[i].x - cx) * (p[i].x - cx) + (p[i].y - cy) * (p[i].y - cy);
    if (d > best) best = d, a = i;
  }
  int b = a;
  best = -1;
  for (int i = 0; i < n; ++i) {
    const double d = (p[i].x - p[a].x) * (p[i].x - p[a].x) + (p[i].y - p[a].y) * (p[i].y - p[a].y);
    if (d > best) best = d, b = i;
  }
  s.vertices.assign({a, b});
  // Intervals as (start, end) with end > start in unwrapped indices (end - start < n).
  s.stack.clear();
  const int b_un = b > a ? b : b + n;
  s.stack.insert(s.stack.end(), {a, b_un, b_un, a + n});
  while (!s.stack.empty()) {
    const int e = s.stack.back();
    s.stack.pop_back();
    const int st = s.stack.back();
    s.stack.pop_back();
    if (e - st < 2) continue;
    const auto& p0 = p[static_cast<std::size_t>(st % n)];
    const auto& p1 = p[static_cast<std::size_t>(e % n)];
    const double dx = p1.x - p0.x, dy = p1.y - p0.y, len = std::hypot(dx, dy);
    double worst = -1;
    int wi = -1;
    // i % n without a division per point: i runs through [st + 1, e), wrapping at most once (e - st < 2 n).
    for (int i = st + 1, k = i % n; i < e; ++i, k = k + 1 == n ? 0 : k + 1) {
      const auto& q = p[static_cast<std::size_t>(k)];
      const double d = len > 1e-9 ? std::abs(dx * (q.y - p0.y) - dy * (q.x - p0.x)) / len
                                  : std::hypot(q.x - p0.x, q.y - p0.y);
      if (d > worst) worst = d, wi = i;
    }
    if (worst <= tol) continue;
    s.vertices.push_back(wi % n);
    // Split points are interior to disjoint intervals, hence distinct; only the first two can
    // coincide (a == b): one more than the limit is still possible after the unique below.
    if (static_cast<int>(s.vertices.size()) > max_vertices + 1) return false;
    s.stack.insert(s.stack.end(), {st, wi, wi, e});
  }
  std::sort(s.vertices.begin(), s.vertices.end());
  s.vertices.erase(std::unique(s.vertices.begin(), s.vertices.end()), s.vertices.end());
  return true;
}

}  // namespace

std::optional<Corners> fit_quad_occluded(std::span<const BoundaryPoint> group, const ImageF& img, double min_angle_deg, double min_area,
                                         const OccludedQuadFitOptions& opt, OccludedQuadFitScratch& s) {
  if (group.size() < static_cast<std::size_t>(std::max(16, opt.min_group_points))) return std::nullopt;
  const auto [xmin, xmax, ymin, ymax] = bounding_box(group);
  if (0.25 * (xmax - xmin) * (ymax - ymin) < min_area) return std::nullopt;
  const float cx = 0.25f * static_cast<float>(xmin + xmax) + 0.0256f, cy = 0.25f * static_cast<float>(ymin + ymax) - 0.0143f;
  // Only the points whose dark side faces the centre: the square's own outline. When the occluder
  // joins the square to a dark background, the group also holds the white ring's outer outline, whose
  // dark side faces away.
  s.order.clear();
  for (std::uint32_t i = 0; i < group.size(); ++i) {
    const BoundaryPoint& p = group[i];
    const float x = 0.5f * static_cast<float>(p.x2), y = 0.5f * static_cast<float>(p.y2);
    // The image's own gradient (dark to light) there: the pixel steps' (gx, gy) are too coarse, a
    // staircase's risers are perpendicular to the outline.
    const int ix = (p.x2 + 1) >> 1, iy = (p.y2 + 1) >> 1;
    float gx = static_cast<float>(p.gx), gy = static_cast<float>(p.gy);
    if (ix > 0 && iy > 0 && ix + 1 < img.width && iy + 1 < img.height)
      gx = img.at(ix + 1, iy) - img.at(ix - 1, iy), gy = img.at(ix, iy + 1) - img.at(ix, iy - 1);
    const float rx = x - cx, ry = y - cy;
    if (rx * gx + ry * gy > opt.min_radial_cos * std::sqrt((rx * rx + ry * ry) * (gx * gx + gy * gy)))
      s.order.push_back(angle_key(pseudo_angle(rx, ry), i));
  }
  if (s.order.size() < 16) return std::nullopt;
  sort_angle_keys(s.order, s.sort);  // equal angles in scan order
  s.pts.resize(s.order.size());
  for (std::size_t i = 0; i < s.order.size(); ++i) {
    const BoundaryPoint& p = group[index_of(s.order[i])];
    s.pts[i] = {0.5f * static_cast<float>(p.x2), 0.5f * static_cast<float>(p.y2)};
  }

  const int n = static_cast<int>(s.pts.size());

  // 1. Straight runs.
  if (!split_runs(s, opt.split_tolerance_px, opt.max_runs)) return std::nullopt;
  const int nv = static_cast<int>(s.vertices.size());
  if (nv < 4 || nv > opt.max_runs) return std::nullopt;

  // 2. Runs merged into lines (longest run first). A run's end points are its corners, left out.
  struct Run {
    RunMoments m;
    int first, last;  // unwrapped indices, inclusive
  };
  std::vector<Run> runs;
  runs.reserve(static_cast<std::size_t>(nv));
  for (int k = 0; k < nv; ++k) {
    const int st = s.vertices[static_cast<std::size_t>(k)];
    int e = s.vertices[static_cast<std::size_t>((k + 1) % nv)];
    if (e <= st) e += n;
    if (e - st < 4) continue;  // under 3 interior points: no direction
    Run r{{}, st + 1, e - 1};
    for (int i = r.first; i <= r.last; ++i) r.m.add(s.pts[static_cast<std::size_t>(i % n)].x, s.pts[static_cast<std::size_t>(i % n)].y);
    runs.push_back(r);
  }
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.m.n > b.m.n; });
  const double cos_merge = std::cos(opt.merge_angle_deg * M_PI / 180.0);
  std::vector<RunLine> lines;
  std::vector<std::vector<int>> members;  // run indices per line
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const RunLine lr = fit(runs[r].m);
    bool merged = false;
    for (std::size_t g = 0; g < lines.size() && !merged; ++g) {
      RunLine& lg = lines[g];
      // A short run's direction is noise (a pixel staircase): only the joint fit decides.
      if (lr.count >= 10 && std::abs(lg.nx * lr.nx + lg.ny * lr.ny) < cos_merge) continue;
      RunMoments m = lg.m;
      m.add(runs[r].m);
      const RunLine both = fit(m);
      if (both.mse > opt.max_line_mse || std::abs(distance(both, lr.cx, lr.cy)) > opt.merge_distance_px) continue;
      lg = both;
      members[g].push_back(static_cast<int>(r));
      merged = true;
    }
    if (!merged && lr.mse <= opt.max_line_mse) {
      lines.push_back(lr);
      members.push_back({static_cast<int>(r)});
    }
  }
  std::vector<int> order(lines.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lines[a].count > lines[b].count; });
  if (order.size() > static_cast<std::size_t>(opt.max_lines)) order.resize(static_cast<std::size_t>(opt.max_lines));
  const int nl = static_cast<int>(order.size());
  if (nl < 4) return std::nullopt;

  s.line_of.assign(static_cast<std::size_t>(n), -1);
  for (int li = 0; li < nl; ++li)
    for (int r : members[static_cast<std::size_t>(order[static_cast<std::size_t>(li)])])
      for (int i = runs[static_cast<std::size_t>(r)].first; i <= runs[static_cast<std::size_t>(r)].last; ++i)
        s.line_of[static_cast<std::size_t>(i % n)] = li;

  // 3. Every set of four lines.
  const double max_dot = std::cos(min_angle_deg * M_PI / 180.0);
  // A candidate quad's score (points on its lines), or -1 when a filter rejects it. lid[k] is side
  // k's line (-1: the side was constructed, see below).
  const auto evaluate = [&](const Corners& q, const std::array<int, 4>& lid) -> int {
    bool ok = true;
    const bool three = lid[3] < 0;
    if (0.5 * twice_signed_area(q) < min_area) return -1;
    for (std::size_t i = 0; i < 4 && ok; ++i) {
      const Eigen::Vector2d d1 = q[(i + 1) & 3] - q[i], d2 = q[(i + 2) & 3] - q[(i + 1) & 3];
      const double den = d1.norm() * d2.norm();
      if (den == 0 || std::abs(d1.dot(d2)) / den > max_dot || d1.x() * d2.y() - d1.y() * d2.x() < 0) ok = false;
    }
    if (!ok) return -1;
    // Side k runs from corner k - 1 to corner k. Coverage in 20 bins along it; points off the
    // four lines must not be inside.
    std::array<std::uint32_t, 4> bins{};
    int inside = 0, on = 0;
    const double tol = opt.inside_tolerance_px;
    for (int i = 0; i < n; ++i) {
      const auto& p = s.pts[static_cast<std::size_t>(i)];
      const int li = s.line_of[static_cast<std::size_t>(i)];
      int k = -1;
      for (int j = 0; j < 4; ++j)
        if (lid[j] == li) k = j;
      if (k >= 0) {
        const Eigen::Vector2d &c0 = q[static_cast<std::size_t>((k + 3) & 3)], &c1 = q[static_cast<std::size_t>(k)];
        const Eigen::Vector2d dir = c1 - c0;
        const double t = (Eigen::Vector2d(p.x, p.y) - c0).dot(dir) / dir.squaredNorm();
        if (t >= 0 && t < 1) bins[static_cast<std::size_t>(k)] |= 1u << static_cast<int>(t * 20);
        ++on;
        continue;
      }
      bool in = true;
      for (int j = 0; j < 4 && in; ++j) {
        const Eigen::Vector2d &c0 = q[static_cast<std::size_t>((j + 3) & 3)], &c1 = q[static_cast<std::size_t>(j)];
        const Eigen::Vector2d dir = (c1 - c0).normalized();
        // Clockwise on screen with y down: the inside is to the right of the direction, i.e. along (-dy, dx).
        const double into = (Eigen::Vector2d(p.x, p.y) - c0).dot(Eigen::Vector2d(-dir.y(), dir.x()));
        in = into > tol;
      }
      inside += in;
    }
    if (inside > opt.max_inside_outliers * n) return -1;
    double total = 0;
    for (int k = 0; k < 4 && ok; ++k) {
      if (lid[k] < 0) continue;  // a side constructed from its neighbours' ends
      const double cover = std::popcount(bins[static_cast<std::size_t>(k)]) / 20.0;
      if (cover < (three ? opt.min_three_side_coverage : opt.min_side_fraction)) ok = false;
      total += cover;
    }
    if (!ok || (!three && total < opt.min_total_coverage)) return -1;
    return on;
  };

  double best_score = -1;
  Corners best{};
  for (int a = 0; a < nl; ++a)
    for (int b = a + 1; b < nl; ++b)
      for (int c = b + 1; c < nl; ++c)
        for (int d = c + 1; d < nl; ++d) {
          std::array<int, 4> set = {a, b, c, d};
          std::array<double, 4> ang{};
          for (int k = 0; k < 4; ++k) {
            const RunLine& l = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(set[k])])];
            ang[k] = pseudo_angle(static_cast<float>(l.cx - cx), static_cast<float>(l.cy - cy));
          }
          // Sort the set by the angle of each line's centroid around the centre.
          std::array<int, 4> idx = {0, 1, 2, 3};
          std::sort(idx.begin(), idx.end(), [&](int u, int v) { return ang[u] < ang[v]; });
          std::array<const RunLine*, 4> L{};
          std::array<int, 4> lid{};
          for (int k = 0; k < 4; ++k) {
            lid[k] = set[static_cast<std::size_t>(idx[k])];
            L[k] = &lines[static_cast<std::size_t>(order[static_cast<std::size_t>(lid[k])])];
          }
          Corners q;
          bool ok = true;
          for (int k = 0; k < 4 && ok; ++k) {  // corner k: side k meets side k + 1
            const RunLine &u = *L[k], &v = *L[(k + 1) & 3];
            if (std::abs(u.nx * v.nx + u.ny * v.ny) > max_dot) { ok = false; break; }
            const double det = u.nx * v.ny - u.ny * v.nx;
            const double du = u.nx * u.cx + u.ny * u.cy, dv = v.nx * v.cx + v.ny * v.cy;
            q[static_cast<std::size_t>(k)] = Eigen::Vector2d((du * v.ny - dv * u.ny) / det, (u.nx * dv - v.nx * du) / det);
          }
          if (!ok) continue;
          // Most of the outline must be on the four lines (an occluder's outline is short); and a set
          // that cannot beat the best is not evaluated (the evaluation walks every point).
          int upper = 0;
          for (int k = 0; k < 4; ++k) upper += L[k]->count;
          if (upper < opt.min_on_lines * n || upper <= best_score) continue;
          const int score = evaluate(q, lid);
          if (score > best_score) best_score = score, best = q;
        }
  // 4. No four lines: three sides seen in full and the fourth hidden but for pieces (or wholly):
  // the fourth side joins the far ends of the two sides beside it (occlusion_refit.hpp later fits
  // it to its visible parts).
  const auto intersect = [](const RunLine& u, const RunLine& v) {
    const double det = u.nx * v.ny - u.ny * v.nx;
    const double du = u.nx * u.cx + u.ny * u.cy, dv = v.nx * v.cx + v.ny * v.cy;
    return Eigen::Vector2d((du * v.ny - dv * u.ny) / det, (u.nx * dv - v.nx * du) / det);
  };
  // The far end of line li's points, seen from corner c, projected onto the line.
  const auto far_end = [&](int li, const Eigen::Vector2d& c) {
    const RunLine& l = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(li)])];
    Eigen::Vector2d dir(-l.ny, l.nx);
    if (dir.dot(Eigen::Vector2d(l.cx, l.cy) - c) < 0) dir = -dir;
    double t = 0;
    for (int i = 0; i < n; ++i)
      if (s.line_of[static_cast<std::size_t>(i)] == li)
        t = std::max(t, (Eigen::Vector2d(s.pts[static_cast<std::size_t>(i)].x, s.pts[static_cast<std::size_t>(i)].y) - c).dot(dir));
    return Eigen::Vector2d(c + t * dir);
  };
  if (best_score < 0 && opt.three_sides)
    for (int a = 0; a < nl; ++a)
      for (int b = a + 1; b < nl; ++b)
        for (int c = b + 1; c < nl; ++c) {
          std::array<int, 3> set = {a, b, c};
          std::array<double, 3> ang{};
          for (int k = 0; k < 3; ++k) {
            const RunLine& l = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(set[k])])];
            ang[k] = pseudo_angle(static_cast<float>(l.cx - cx), static_cast<float>(l.cy - cy));
          }
          std::array<int, 3> idx = {0, 1, 2};
          std::sort(idx.begin(), idx.end(), [&](int u, int v) { return ang[static_cast<std::size_t>(u)] < ang[static_cast<std::size_t>(v)]; });
          set = {set[static_cast<std::size_t>(idx[0])], set[static_cast<std::size_t>(idx[1])], set[static_cast<std::size_t>(idx[2])]};
          for (int rot = 0; rot < 3; ++rot) {
            const int la = set[rot], lb = set[(rot + 1) % 3], lc = set[(rot + 2) % 3];
            const RunLine &A = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(la)])];
            const RunLine &B = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(lb)])];
            const RunLine &C = lines[static_cast<std::size_t>(order[static_cast<std::size_t>(lc)])];
            if (std::abs(A.nx * B.nx + A.ny * B.ny) > max_dot || std::abs(B.nx * C.nx + B.ny * C.ny) > max_dot) continue;
            const Eigen::Vector2d cab = intersect(A, B), cbc = intersect(B, C);
            const Corners q = {cab, cbc, far_end(lc, cbc), far_end(la, cab)};
            const int score = evaluate(q, {la, lb, lc, -1});
            if (score > best_score) best_score = score, best = q;
          }
        }
  if (best_score < 0) return std::nullopt;
  return best;
}

}  // namespace tagbench
