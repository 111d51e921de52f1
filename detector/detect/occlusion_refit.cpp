#include "detect/occlusion_refit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace tagbench {
namespace {

// Pixel centres at integers, clamped at the border; with gamma != 1 each pixel is raised to it before
// it is interpolated (an encoded pixel linearised, as linear_corners.hpp does).
float bilinear(const ImageF& img, double x, double y, double gamma = 1.0) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const float ax = static_cast<float>(x - fx), ay = static_cast<float>(y - fy);
  const auto at = [&](int u, int v) { return linearised(img.at_clamped(u, v), gamma); };
  const float a = at(x0, y0), b = at(x0 + 1, y0), c = at(x0, y0 + 1), d = at(x0 + 1, y0 + 1);
  return (a + (b - a) * ax) * (1 - ay) + (c + (d - c) * ax) * ay;
}

struct Side {
  Eigen::Vector2d p0, dir, n;  // a point, unit direction, unit outward normal
  double len = 0;
};

std::optional<Eigen::Vector2d> intersect(const Side& a, const Side& b) {
  const double det = a.dir.x() * b.dir.y() - a.dir.y() * b.dir.x();
  if (std::abs(det) < 1e-9) return std::nullopt;
  const Eigen::Vector2d d = b.p0 - a.p0;
  const double t = (d.x() * b.dir.y() - d.y() * b.dir.x()) / det;
  return a.p0 + t * a.dir;
}

}  // namespace

OcclusionRefitResult refit_occluded_sides(const ImageF& img, const Corners& corners, int cells_across,
                                          const OcclusionRefitOptions& opt) {
  OcclusionRefitResult res;
  const Eigen::Vector2d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  std::array<Side, 4> sides;
  std::array<std::vector<double>, 4> ts, contrast;
  std::vector<double> all;
  if (!(opt.gamma > 0 && std::isfinite(opt.gamma))) {  // no locator: kept as it is
    res.corners = corners;
    return res;
  }
  double perimeter = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = corners[i], b = corners[(i + 1) & 3];
    Side& s = sides[i];
    s.p0 = a;
    s.len = (b - a).norm();
    if (!(s.len > 1e-6)) return res;
    s.dir = (b - a) / s.len;
    s.n = Eigen::Vector2d(-s.dir.y(), s.dir.x());
    if (s.n.dot(0.5 * (a + b) - centre) < 0) s.n = -s.n;
    perimeter += s.len;
  }
  // Per side, the cell size across it (the distance to the opposite side over the cells across):
  // on small or steeply slanted tags the rings are too thin to judge, and the detection is kept as it is.
  std::array<double, 4> cells{};
  for (std::size_t i = 0; i < 4; ++i) {
    const Side& o = sides[(i + 2) & 3];
    cells[i] = std::abs((o.p0 + 0.5 * o.len * o.dir - sides[i].p0).dot(sides[i].n)) / cells_across;
    if (cells[i] < opt.min_cell_px) {
      res.corners = corners;
      return res;
    }
  }
  const double cell = perimeter / 4 / cells_across;
  for (std::size_t i = 0; i < 4; ++i) {
    const Side& s = sides[i];
    const double cell = cells[i];
    const double margin = std::min(opt.end_margin_px, 0.25 * s.len);
    const int count = std::max(4, static_cast<int>((s.len - 2 * margin) / opt.sample_spacing_px) + 1);
    for (int k = 0; k < count; ++k) {
      const double t = margin + (s.len - 2 * margin) * k / (count - 1);
      const Eigen::Vector2d p = s.p0 + t * s.dir, in = p - 0.5 * cell * s.n, out = p + 0.5 * cell * s.n;
      const double vi = bilinear(img, in.x(), in.y()), vo = bilinear(img, out.x(), out.y());
      const double c = (vo - vi) / std::max(1e-6, vo + vi);
      ts[i].push_back(t);
      contrast[i].push_back(c);
      all.push_back(c);
    }
  }
  std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2), all.end());
  const double median = all[all.size() / 2];
  if (median < opt.min_median_contrast) {  // too faint to judge (a worn print, deep shade): kept as it is
    res.corners = corners;
    return res;
  }
  const double limit = opt.agree_fraction * median;

  std::array<Side, 4> fitted = sides;
  for (std::size_t i = 0; i < 4; ++i) {
    const int count = static_cast<int>(contrast[i].size());
    std::vector<char> ok(static_cast<std::size_t>(count));
    int disagree = 0;
    for (int k = 0; k < count; ++k) disagree += !(ok[static_cast<std::size_t>(k)] = contrast[i][static_cast<std::size_t>(k)] >= limit);
    if (disagree <= opt.max_disagree * count) continue;
    std::vector<char> keep = ok;
    for (int k = 0; k < count; ++k)
      if (!ok[static_cast<std::size_t>(k)])
        for (int j = std::max(0, k - opt.erode_samples); j <= std::min(count - 1, k + opt.erode_samples); ++j)
          keep[static_cast<std::size_t>(j)] = 0;
    int visible = 0;
    double first = 1, last = 0;
    for (int k = 0; k < count; ++k) {
      visible += keep[static_cast<std::size_t>(k)];
      if (keep[static_cast<std::size_t>(k)]) continue;
      first = std::min(first, ts[i][static_cast<std::size_t>(k)] / sides[i].len);
      last = std::max(last, ts[i][static_cast<std::size_t>(k)] / sides[i].len);
    }
    if (visible < std::max(3.0, opt.min_visible * count)) return res;  // too little of this side to fix its line

    const double range = std::clamp(0.45 * cells[i], 1.0, 2.5), step = 0.25, h = 0.5;
    for (int it = 0; it < opt.iterations; ++it) {
      Side& s = fitted[i];
      double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
      for (int k = 0; k < count; ++k) {
        if (!keep[static_cast<std::size_t>(k)]) continue;
        // The sample's position along the ORIGINAL side, projected onto the current line.
        const Eigen::Vector2d q0 = sides[i].p0 + ts[i][static_cast<std::size_t>(k)] * sides[i].dir;
        const Eigen::Vector2d p = s.p0 + (q0 - s.p0).dot(s.dir) * s.dir;
        double w = 0, ws = 0;
        for (double o = -range; o <= range + 1e-9; o += step) {
          const Eigen::Vector2d a = p + (o + h) * s.n, b = p + (o - h) * s.n;
          const double d = bilinear(img, a.x(), a.y(), opt.gamma) - bilinear(img, b.x(), b.y(), opt.gamma);
          if (d <= 0) continue;
          w += d * d, ws += d * d * o;
        }
        if (!(w > 0)) continue;
        const Eigen::Vector2d e = p + (ws / w) * s.n;
        sw += w, sx += w * e.x(), sy += w * e.y(), sxx += w * e.x() * e.x(), sxy += w * e.x() * e.y(), syy += w * e.y() * e.y();
      }
      if (!(sw > 0)) return res;
      const double mx = sx / sw, my = sy / sw;
      const double cxx = sxx / sw - mx * mx, cxy = sxy / sw - mx * my, cyy = syy / sw - my * my;
      const double theta = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // direction of the largest spread
      Eigen::Vector2d dir(std::cos(theta), std::sin(theta));
      if (dir.dot(sides[i].dir) < 0) dir = -dir;
      s.p0 = Eigen::Vector2d(mx, my);
      s.dir = dir;
      s.n = Eigen::Vector2d(-dir.y(), dir.x());
      if (s.n.dot(sides[i].n) < 0) s.n = -s.n;
    }
    ++res.sides_refitted;
    res.hidden[i] = std::array<double, 2>{first, last};
  }
  Corners out = corners;
  if (res.sides_refitted > 0)
    for (std::size_t i = 0; i < 4; ++i) {  // corner i + 1 is where side i meets side i + 1
      const auto c = intersect(fitted[i], fitted[(i + 1) & 3]);
      if (!c) return res;
      if ((*c - corners[(i + 1) & 3]).norm() > opt.max_corner_shift_cells * cell) return res;
      out[(i + 1) & 3] = *c;
    }
  res.corners = out;
  return res;
}

}  // namespace tagbench
