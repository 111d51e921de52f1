#include "detect/edge_refine.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/payload_decode.hpp"  // sample_bilinear

namespace tagbench {
namespace {

struct SideLine {
  Eigen::Vector2d point, dir;  // dir unit
};

std::optional<Eigen::Vector2d> intersect(const SideLine& a, const SideLine& b) {
  const double den = a.dir.x() * b.dir.y() - a.dir.y() * b.dir.x();
  if (std::abs(den) < 1e-9) return std::nullopt;
  const Eigen::Vector2d d = b.point - a.point;
  const double t = (d.x() * b.dir.y() - d.y() * b.dir.x()) / den;
  return a.point + t * a.dir;
}

// Total least squares through weighted points; nullopt for fewer than 3 points or no spread.
std::optional<SideLine> fit_line(const std::vector<Eigen::Vector3d>& pts) {  // (x, y, w)
  if (pts.size() < 3) return std::nullopt;
  double W = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : pts) {
    W += p.z();
    c += p.z() * p.head<2>();
  }
  if (!(W > 0)) return std::nullopt;
  c /= W;
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector2d v = p.head<2>() - c;
    C += p.z() * v * v.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
  if (es.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector2d dir = es.eigenvectors().col(1);  // largest eigenvalue
  if (!dir.allFinite() || !(es.eigenvalues()(1) > 0)) return std::nullopt;
  return SideLine{c, dir.normalized()};
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool convex_same_winding(const Corners& a, const Corners& b) {
  for (std::size_t i = 0; i < 4; ++i) {
    const auto ea0 = a[(i + 1) % 4] - a[i], ea1 = a[(i + 2) % 4] - a[(i + 1) % 4];
    const auto eb0 = b[(i + 1) % 4] - b[i], eb1 = b[(i + 2) % 4] - b[(i + 1) % 4];
    if (cross(ea0, ea1) * cross(eb0, eb1) <= 0) return false;
  }
  return true;
}

}  // namespace

// The same doubles in the same operations as sample_bilinear_inside, two steps at a time with SSE2
// (every lane rounds as the scalar code does).
void detail::sample_scan(const ImageF& img, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
                 const std::vector<EdgeRefineScratch::Step>& steps, float* value) {
  std::size_t j = 0;
#if defined(__SSE2__)
  if (img.width >= 2 && img.height >= 2) {
    const __m128d px = _mm_set1_pd(p.x()), py = _mm_set1_pd(p.y()), nx = _mm_set1_pd(n.x()), ny = _mm_set1_pd(n.y());
    for (; j + 2 <= steps.size(); j += 2) {
      const __m128d off = _mm_set_pd(steps[j + 1].hi, steps[j].hi);
      const __m128d qx = _mm_add_pd(px, _mm_mul_pd(off, nx)), qy = _mm_add_pd(py, _mm_mul_pd(off, ny));
      sample_bilinear_inside_pair(img, qx, qy, value + j);
    }
  }
#endif
  BilinearCell cell;
  for (; j < steps.size(); ++j) value[j] = sample_bilinear_inside(img, p + steps[j].hi * n, cell);
}

namespace {

// One pass: every side re-located around the lines through `c`.
std::optional<Corners> refine_once(const ImageF& img, const Corners& c, const EdgeRefineOptions& opt,
                                   EdgeRefineScratch& scratch) {
  const Eigen::Vector2d centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  // A scan samples I at s + h and at s - h for every step s; s - h of step j is s + h of step j - m
  // (m = 2 h / step) when the two offsets are equal as doubles, as they are when the steps add
  // exactly (0.25 px steps from a range under 4 px do): that sample is then reused, not taken again.
  // The comparison keeps the result identical to sampling both every time.
  const int m = static_cast<int>(std::lround(2 * opt.derivative_half_px / opt.step_px));
  const double h = opt.derivative_half_px;
  const auto gradient = [&](float hi, float lo) -> double {
    return opt.gamma == 1.0 ? hi - lo : std::pow(std::max(0.0f, hi), opt.gamma) - std::pow(std::max(0.0f, lo), opt.gamma);
  };
  const auto inside = [&](const Eigen::Vector2d& q) {  // sample_bilinear's domain
    return q.x() >= 0 && q.y() >= 0 && q.x() <= img.width - 1 && q.y() <= img.height - 1;
  };
  std::array<SideLine, 4> lines;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = c[i], b = c[(i + 1) % 4];
    const double len = (b - a).norm();
    if (!(len > 1e-6)) return std::nullopt;
    const Eigen::Vector2d dir = (b - a) / len;
    Eigen::Vector2d n(dir.y(), -dir.x());
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;  // outward, whatever the winding
    lines[i] = SideLine{a, dir};
    const double range =
        std::clamp(opt.range_cell_fraction * len / opt.cells_across, opt.min_range_px, opt.max_range_px);
    const int samples = std::max(opt.min_samples, static_cast<int>(std::lround(len / opt.sample_spacing_px)));
    // The side's scan steps, and the smallest and largest offset sampled.
    auto& steps = scratch.steps;
    steps.clear();
    double lo_end = HUGE_VAL, hi_end = -HUGE_VAL;
    for (double s = -range; s <= range + 1e-9; s += opt.step_px) {
      EdgeRefineScratch::Step st{s, s + h, s - h, -1};
      const std::size_t j = steps.size();
      if (m >= 1 && j >= static_cast<std::size_t>(m) && steps[j - static_cast<std::size_t>(m)].hi == st.lo)
        st.lo_from = static_cast<int>(j) - m;
      lo_end = std::min({lo_end, st.lo, st.hi});
      hi_end = std::max({hi_end, st.lo, st.hi});
      steps.push_back(st);
    }
    scratch.value.resize(steps.size());
    scratch.value_or_none.resize(steps.size());
    std::vector<Eigen::Vector3d>& pts = scratch.points;
    pts.clear();
    for (int k = 0; k < samples; ++k) {
      const double t = opt.end_margin + (1 - 2 * opt.end_margin) * (k + 0.5) / samples;
      const Eigen::Vector2d p = a + t * (b - a);
      double sw = 0, sws = 0;
      // p + u n is monotone in u coordinate by coordinate (in floating point too), so when the two
      // ends of the scan are inside the image every sample is: no per-sample test.
      if (!img.empty() && inside(p + lo_end * n) && inside(p + hi_end * n)) {
        float* value = scratch.value.data();
        detail::sample_scan(img, p, n, steps, value);  // every step's `hi` sample
        BilinearCell cell_lo;  // a quarter-pixel step mostly stays in the same 2 x 2 pixels
        for (std::size_t j = 0; j < steps.size(); ++j) {
          const EdgeRefineScratch::Step& st = steps[j];
          const float hi = value[j];
          const float lo = st.lo_from >= 0 ? value[st.lo_from] : sample_bilinear_inside(img, p + st.lo * n, cell_lo);
          // A light-to-dark step counts zero, branch-free (the sign of an image's noise is no pattern
          // a branch predictor learns); adding +0 leaves both sums as skipping would.
          const double g0 = gradient(hi, lo), g = g0 > 0 ? g0 : 0.0;
          sw += g * g;
          sws += g * g * st.s;
        }
      } else {
        std::optional<float>* value = scratch.value_or_none.data();
        for (std::size_t j = 0; j < steps.size(); ++j) {
          const EdgeRefineScratch::Step& st = steps[j];
          const auto hi = sample_bilinear(img, p + st.hi * n);
          value[j] = hi;
          const auto lo = st.lo_from >= 0 ? value[st.lo_from] : sample_bilinear(img, p + st.lo * n);
          if (!hi || !lo) continue;
          const double g = gradient(*hi, *lo);
          if (g <= 0) continue;
          sw += g * g;
          sws += g * g * st.s;
        }
      }
      if (sw > 0) pts.emplace_back(p.x() + sws / sw * n.x(), p.y() + sws / sw * n.y(), sw);
    }
    if (const auto l = fit_line(pts)) lines[i] = *l;
  }
  Corners out;
  for (std::size_t i = 0; i < 4; ++i) {  // corner i joins side i-1 (ending there) and side i (starting there)
    const auto p = intersect(lines[(i + 3) % 4], lines[i]);
    if (!p) return std::nullopt;
    out[i] = *p;
  }
  return out;
}

}  // namespace

std::optional<Corners> refine_quad_edges(const ImageF& img, const Corners& c, const EdgeRefineOptions& opt) {
  EdgeRefineScratch scratch;
  return refine_quad_edges(img, c, opt, scratch);
}

std::optional<Corners> refine_quad_edges(const ImageF& img, const Corners& c, const EdgeRefineOptions& opt,
                                         EdgeRefineScratch& scratch) {
  if (img.empty() || opt.cells_across < 1 || !(opt.step_px > 0) || !(opt.derivative_half_px > 0)) return std::nullopt;
  for (const auto& p : c)
    if (!p.allFinite()) return std::nullopt;
  Corners cur = c;
  for (int it = 0; it < std::max(1, opt.iterations); ++it) {
    const auto next = refine_once(img, cur, opt, scratch);
    if (!next) return std::nullopt;
    cur = *next;
    for (std::size_t i = 0; i < 4; ++i)
      if ((cur[i] - c[i]).norm() > opt.max_corner_shift_px) return std::nullopt;
    if (!convex_same_winding(c, cur)) return std::nullopt;
  }
  return cur;
}

}  // namespace tagbench
