#include "detect/edge_refine.hpp"

#include <algorithm>
#include <cmath>

namespace tagbench {
namespace {

// Bilinear intensity, nullopt-free: false when the 2x2 neighbourhood leaves the image.
bool bilinear(const ImageF& img, double x, double y, double& v) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  if (ix < 0 || iy < 0 || ix + 1 >= img.width || iy + 1 >= img.height) return false;
  const double ax = x - fx, ay = y - fy;
  const float* r0 = img.data.data() + img.index(ix, iy);
  const float* r1 = r0 + img.width;
  v = (1 - ay) * ((1 - ax) * r0[0] + ax * r0[1]) + ay * ((1 - ax) * r1[0] + ax * r1[1]);
  return true;
}

struct Line {
  Eigen::Vector2d c, n;  // a point and the unit normal
};

}  // namespace

Corners refine_quad_edges(const ImageF& img, const Corners& q, const EdgeRefineOptions& opt) {
  Line lines[4];
  for (std::size_t e = 0; e < 4; ++e) {
    const Eigen::Vector2d a = q[e], b = q[(e + 1) & 3];
    const Eigen::Vector2d d = b - a;
    const double len = d.norm();
    lines[e] = Line{0.5 * (a + b), len > 0 ? Eigen::Vector2d(d.y() / len, -d.x() / len) : Eigen::Vector2d(0, 0)};
    if (len <= 0) continue;
    const Eigen::Vector2d n = lines[e].n;  // outward for a clockwise-on-screen quad (y down)
    const int samples = std::max(opt.min_samples, static_cast<int>(len / 8));
    const int steps = static_cast<int>(std::floor(2 * opt.search_range / opt.step)) + 1;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    int count = 0;
    for (int s = 0; s < samples; ++s) {
      const double alpha = (1.0 + s) / (samples + 1);
      const Eigen::Vector2d p = a + alpha * d;
      double wsum = 0, wn = 0;
      for (int k = 0; k < steps; ++k) {
        const double off = -opt.search_range + k * opt.step;
        double out, in;
        if (!bilinear(img, p.x() + (off + 1) * n.x(), p.y() + (off + 1) * n.y(), out) ||
            !bilinear(img, p.x() + (off - 1) * n.x(), p.y() + (off - 1) * n.y(), in))
          continue;
        const double g = out - in;  // rises outward at the black square's edge
        if (g <= 0) continue;
        wsum += g * g;
        wn += g * g * off;
      }
      if (wsum <= 0) continue;
      const Eigen::Vector2d e_pt = p + (wn / wsum) * n;
      sx += e_pt.x(), sy += e_pt.y(), sxx += e_pt.x() * e_pt.x(), sxy += e_pt.x() * e_pt.y(), syy += e_pt.y() * e_pt.y();
      ++count;
    }
    if (count < 2) continue;
    const double ex = sx / count, ey = sy / count;
    const double cxx = sxx / count - ex * ex, cxy = sxy / count - ex * ey, cyy = syy / count - ey * ey;
    // The line direction is the covariance's major axis; the normal is perpendicular to it.
    const double theta = 0.5 * std::atan2(2 * cxy, cxx - cyy);
    Eigen::Vector2d nn(-std::sin(theta), std::cos(theta));
    if (nn.dot(n) < 0) nn = -nn;
    lines[e] = Line{Eigen::Vector2d(ex, ey), nn};
  }
  Corners r;
  for (std::size_t i = 0; i < 4; ++i) {  // corner i+1 joins side i and side i+1
    const Line &l0 = lines[i], &l1 = lines[(i + 1) & 3];
    const double det = l0.n.x() * l1.n.y() - l0.n.y() * l1.n.x();
    if (std::abs(det) < 1e-6) return q;
    const double d0 = l0.n.dot(l0.c), d1 = l1.n.dot(l1.c);
    r[(i + 1) & 3] = Eigen::Vector2d((d0 * l1.n.y() - d1 * l0.n.y()) / det, (l0.n.x() * d1 - l1.n.x() * d0) / det);
  }
  return r;
}

}  // namespace tagbench
