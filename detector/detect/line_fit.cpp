#include "detect/line_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>

#include "detect/blur.hpp"

namespace tagbench {

std::optional<Segment> fit_segment(std::span<const ClusterPixel> pixels) {
  // Pass 1: weighted centroid and the weighted mean gradient (for the orientation).
  double sw = 0.0, sx = 0.0, sy = 0.0, gx = 0.0, gy = 0.0;
  for (const ClusterPixel& p : pixels) {
    const double w = p.mag;
    sw += w;
    sx += w * p.x;
    sy += w * p.y;
    gx += w * std::cos(p.theta);
    gy += w * std::sin(p.theta);
  }
  if (!(sw > 0.0)) return std::nullopt;
  const double cx = sx / sw, cy = sy / sw;

  // Pass 2: covariance about the centroid (centred sums avoid cancellation on large coordinates).
  double cxx = 0.0, cxy = 0.0, cyy = 0.0;
  for (const ClusterPixel& p : pixels) {
    const double dx = p.x - cx, dy = p.y - cy;
    cxx += p.mag * dx * dx;
    cxy += p.mag * dx * dy;
    cyy += p.mag * dy * dy;
  }
  // Principal axis of the symmetric 2x2 matrix [[cxx, cxy], [cxy, cyy]] in closed form.
  const double axis = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  Eigen::Vector2d d(std::cos(axis), std::sin(axis));
  // Dark on the left: the mean gradient must point to the right of d (see the header).
  if (d.x() * gy - d.y() * gx < 0.0) d = -d;

  double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
  for (const ClusterPixel& p : pixels) {
    const double t = (p.x - cx) * d.x() + (p.y - cy) * d.y();
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  const Eigen::Vector2d c(cx, cy);
  Segment s;
  s.p0 = c + tmin * d;
  s.p1 = c + tmax * d;
  s.theta = std::atan2(d.y(), d.x());
  if (s.theta <= -std::numbers::pi) s.theta = std::numbers::pi;  // atan2(-0, -1) = -pi; keep (-pi, pi]
  s.length = tmax - tmin;
  return s;
}

std::vector<Segment> fit_segments(const Clusters& clusters, const LineFitOptions& opt) {
  std::vector<Segment> out;
  out.reserve(clusters.size());
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    const std::optional<Segment> s = fit_segment(clusters[i]);
    if (s && s->length >= opt.min_length) out.push_back(*s);
  }
  return out;
}

Segment segment_full_from_half(const Segment& s) {
  Segment f = s;
  f.p0 = {full_from_half(s.p0.x()), full_from_half(s.p0.y())};
  f.p1 = {full_from_half(s.p1.x()), full_from_half(s.p1.y())};
  f.length = 2.0 * s.length;
  return f;
}

}  // namespace tagbench
