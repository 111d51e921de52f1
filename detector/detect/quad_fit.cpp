#include "detect/quad_fit.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tagbench {
namespace {

using Moments = QuadFitScratch::Moments;

struct Line {
  double cx, cy, nx, ny;  // a point on the line (the weighted centroid) and the unit normal
};

// The weighted least-squares line through the cyclic run i0..i1 (inclusive; i0 > i1 wraps).
// Returns the mean squared distance (the covariance's small eigenvalue); err = that x point count.
double fit_run(const std::vector<Moments>& cum, int i0, int i1, Line* line, double* err) {
  const int n = static_cast<int>(cum.size());
  auto at = [&](int i) { return cum[static_cast<std::size_t>(i)]; };
  Moments m{};
  auto add = [&](const Moments& a, double s) {
    m.mx += s * a.mx, m.my += s * a.my, m.mxx += s * a.mxx, m.mxy += s * a.mxy, m.myy += s * a.myy, m.w += s * a.w;
  };
  int count;
  if (i0 <= i1) {
    add(at(i1), 1);
    if (i0 > 0) add(at(i0 - 1), -1);
    count = i1 - i0 + 1;
  } else {
    add(at(n - 1), 1);
    add(at(i0 - 1), -1);
    add(at(i1), 1);
    count = n - i0 + i1 + 1;
  }
  const double ex = m.mx / m.w, ey = m.my / m.w;
  const double cxx = m.mxx / m.w - ex * ex, cxy = m.mxy / m.w - ex * ey, cyy = m.myy / m.w - ey * ey;
  const double root = std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy);
  const double small = std::max(0.0, 0.5 * (cxx + cyy - root));
  if (line) {
    // The normal is the eigenvector of the small eigenvalue; of the two equivalent formulas take the
    // better conditioned one.
    const double big = 0.5 * (cxx + cyy + root);
    double ax = cxx - big, ay = cxy, bx = cxy, by = cyy - big;  // rows of (C - big I): both normal to the line direction
    const double la = ax * ax + ay * ay, lb = bx * bx + by * by;
    double nx = la > lb ? ax : bx, ny = la > lb ? ay : by;
    const double len = std::sqrt(std::max(la, lb));
    if (len > 1e-12) {
      nx /= len;
      ny /= len;
    } else {
      nx = ny = 0;
    }
    *line = Line{ex, ey, nx, ny};
  }
  if (err) *err = count * small;
  return small;
}

// Where the kernel line fit bends: indices of up to max_maxima local maxima of the smoothed
// kernel error, in index order.
void corner_candidates(QuadFitScratch& s, int max_maxima) {
  const int n = static_cast<int>(s.pts.size());
  const int k = std::min(20, n / 12);  // kernel half width, about half the points of a short side
  s.err.resize(static_cast<std::size_t>(n));
  s.smooth.resize(static_cast<std::size_t>(n));
  // Where the run i-k..i+k neither wraps nor starts at 0 (i - k >= 1, i + k < n) its moments are one
  // difference of the cumulative sums: that stretch (most points) inlined, every operation as in
  // fit_run and in the same order, so the errors are the same numbers.
  const int lo = std::min(n, k + 1), hi = std::max(lo, n - k);
  for (int i = 0; i < lo; ++i)  // (i - k) mod n and (i + k) mod n without a division (k < n)
    fit_run(s.cum, i >= k ? i - k : i + n - k, i + k < n ? i + k : i + k - n, nullptr, &s.err[static_cast<std::size_t>(i)]);
  detail::kernel_errors(s.cum.data(), k, lo, hi, s.err.data());
  for (int i = hi; i < n; ++i)
    fit_run(s.cum, i >= k ? i - k : i + n - k, i + k < n ? i + k : i + k - n, nullptr, &s.err[static_cast<std::size_t>(i)]);
  // Smooth with a 7-tap Gaussian (sigma 1 point), cyclically, so noise gives fewer false maxima.
  static constexpr double g[7] = {0.011109, 0.135335, 0.606531, 1.0, 0.606531, 0.135335, 0.011109};
  for (int i = 0; i < n; ++i) {
    double acc = 0;
    if (i >= 3 && i + 3 < n) {  // no wrap: the common case, without a modulo per tap
      const double* e = s.err.data() + i - 3;
      for (int j = 0; j < 7; ++j) acc += g[j] * e[j];
    } else {
      for (int j = -3; j <= 3; ++j) acc += g[j + 3] * s.err[static_cast<std::size_t>((i + j + 3 * n) % n)];
    }
    s.smooth[static_cast<std::size_t>(i)] = acc;
  }
  s.maxima.clear();
  for (int i = 0; i < n; ++i) {
    const double e = s.smooth[static_cast<std::size_t>(i)];
    if (e > s.smooth[static_cast<std::size_t>(i + 1 < n ? i + 1 : 0)] && e > s.smooth[static_cast<std::size_t>(i > 0 ? i - 1 : n - 1)])
      s.maxima.push_back(i);
  }
  if (static_cast<int>(s.maxima.size()) > max_maxima) {
    std::nth_element(s.maxima.begin(), s.maxima.begin() + max_maxima, s.maxima.end(), [&](int a, int b) {
      return s.smooth[static_cast<std::size_t>(a)] > s.smooth[static_cast<std::size_t>(b)];
    });
    s.maxima.resize(static_cast<std::size_t>(max_maxima));
    std::sort(s.maxima.begin(), s.maxima.end());
  }
}

// Whether the outer outline is tried on `group`, by its bounding box (one pass over the points): the
// box's longer side at most outer.max_size_px, and at least outer.min_points_per_box_px points per px
// of its width plus height.
bool outline_box_admits(std::span<const BoundaryPoint> group, const OuterOutlineOptions& outer) {
  const auto [xmin, xmax, ymin, ymax] = bounding_box(group);
  const double w = 0.5 * (xmax - xmin), h = 0.5 * (ymax - ymin);
  return std::max(w, h) <= outer.max_size_px && static_cast<double>(group.size()) >= outer.min_points_per_box_px * (w + h);
}

}  // namespace

void detail::kernel_errors(const QuadFitScratch::Moments* cum, int k, int lo, int hi, double* err) {
  const double count = 2 * k + 1;
  int i = lo;
#if defined(__SSE2__)
  // Two points at a time: every lane the scalar loop's operations in its order (divisions, square
  // root and max are correctly rounded alike), so the same numbers; the divisions, the loop's cost,
  // go two by two.
  const __m128d zero = _mm_setzero_pd(), half = _mm_set1_pd(0.5), four = _mm_set1_pd(4), cnt = _mm_set1_pd(count);
  for (; i + 2 <= hi; i += 2) {
    const Moments &a0 = cum[i + k], &a1 = cum[i + 1 + k], &b0 = cum[i - k - 1], &b1 = cum[i - k];
    const auto diff = [](double a0v, double a1v, double b0v, double b1v) {
      return _mm_sub_pd(_mm_set_pd(a1v, a0v), _mm_set_pd(b1v, b0v));
    };
    const __m128d mx = diff(a0.mx, a1.mx, b0.mx, b1.mx), my = diff(a0.my, a1.my, b0.my, b1.my);
    const __m128d mxx = diff(a0.mxx, a1.mxx, b0.mxx, b1.mxx), mxy = diff(a0.mxy, a1.mxy, b0.mxy, b1.mxy);
    const __m128d myy = diff(a0.myy, a1.myy, b0.myy, b1.myy), mw = diff(a0.w, a1.w, b0.w, b1.w);
    const __m128d ex = _mm_div_pd(mx, mw), ey = _mm_div_pd(my, mw);
    const __m128d cxx = _mm_sub_pd(_mm_div_pd(mxx, mw), _mm_mul_pd(ex, ex));
    const __m128d cxy = _mm_sub_pd(_mm_div_pd(mxy, mw), _mm_mul_pd(ex, ey));
    const __m128d cyy = _mm_sub_pd(_mm_div_pd(myy, mw), _mm_mul_pd(ey, ey));
    const __m128d d = _mm_sub_pd(cxx, cyy);
    const __m128d root = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(d, d), _mm_mul_pd(_mm_mul_pd(four, cxy), cxy)));
    // std::max(0.0, v) is v when 0 < v, else 0 (NaN included): maxpd(v, 0) is v when v > 0, else 0.
    const __m128d e = _mm_max_pd(_mm_mul_pd(half, _mm_sub_pd(_mm_add_pd(cxx, cyy), root)), zero);
    _mm_storeu_pd(err + i, _mm_mul_pd(cnt, e));
  }
#endif
  for (; i < hi; ++i) {
    const Moments& a = cum[i + k];
    const Moments& b = cum[i - k - 1];
    const double mx = a.mx - b.mx, my = a.my - b.my, mxx = a.mxx - b.mxx, mxy = a.mxy - b.mxy, myy = a.myy - b.myy,
                 mw = a.w - b.w;
    const double ex = mx / mw, ey = my / mw;
    const double cxx = mxx / mw - ex * ex, cxy = mxy / mw - ex * ey, cyy = myy / mw - ey * ey;
    const double root = std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy);
    err[i] = count * std::max(0.0, 0.5 * (cxx + cyy - root));
  }
}

std::optional<Corners> fit_quad(std::span<const BoundaryPoint> group, const ImageF& img, const QuadFitOptions& opt,
                                QuadFitScratch& s) {
  const int n = static_cast<int>(group.size());
  if (n < std::max(opt.min_points, 4) || n > 2 * (2 * img.width + 2 * img.height)) return std::nullopt;

  // Bounding box (doubled coordinates), then the cheap size test: the box holds the quad.
  const auto [xmin, xmax, ymin, ymax] = bounding_box(group);
  const double min_area = 0.95 * opt.min_tag_width * opt.min_tag_width;
  if (0.25 * (xmax - xmin) * (ymax - ymin) < min_area) return std::nullopt;

  // A centre slightly off the half-pixel lattice so no point sits exactly on it.
  const float cx = 0.25f * static_cast<float>(xmin + xmax) + 0.0256f, cy = 0.25f * static_cast<float>(ymin + ymax) - 0.0143f;
  // The polarity first (about half the groups of a natural image have the wrong one), then the
  // points' weights, which read the image.
  double outward = 0;
  for (int i = 0; i < n; ++i) {
    const BoundaryPoint& p = group[static_cast<std::size_t>(i)];
    const float x = 0.5f * static_cast<float>(p.x2), y = 0.5f * static_cast<float>(p.y2);
    outward += (x - cx) * p.gx + (y - cy) * p.gy;
  }
  if (outward > 0 ? !opt.dark_inside : !opt.light_inside) return std::nullopt;
  // Sorted by angle (equal angles in scan order), then weighted in that order.
  s.order.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const BoundaryPoint& p = group[static_cast<std::size_t>(i)];
    s.order[static_cast<std::size_t>(i)] = angle_key(
        pseudo_angle(0.5f * static_cast<float>(p.x2) - cx, 0.5f * static_cast<float>(p.y2) - cy), static_cast<std::uint32_t>(i));
  }
  sort_angle_keys(s.order, s.sort);
  s.pts.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const BoundaryPoint& p = group[index_of(s.order[static_cast<std::size_t>(i)])];
    const float x = 0.5f * static_cast<float>(p.x2), y = 0.5f * static_cast<float>(p.y2);
    const int ix = (p.x2 + 1) >> 1, iy = (p.y2 + 1) >> 1;
    float wgt = 1;
    if (ix > 0 && iy > 0 && ix + 1 < img.width && iy + 1 < img.height) {
      const float gx = img.at(ix + 1, iy) - img.at(ix - 1, iy), gy = img.at(ix, iy + 1) - img.at(ix, iy - 1);
      wgt = 255.0f * std::sqrt(gx * gx + gy * gy) + 1;  // on 0..255 intensities, as AprilTag 3 weighs them
    }
    s.pts[static_cast<std::size_t>(i)] = {x, y, wgt};
  }

  s.cum.resize(static_cast<std::size_t>(n));
  Moments m{};
  for (int i = 0; i < n; ++i) {
    const auto& p = s.pts[static_cast<std::size_t>(i)];
    const double x = p.x, y = p.y, w = p.w;
    m.mx += w * x, m.my += w * y, m.mxx += w * x * x, m.mxy += w * x * y, m.myy += w * y * y, m.w += w;
    s.cum[static_cast<std::size_t>(i)] = m;
  }
  if (std::min(20, n / 12) < 2) return std::nullopt;
  corner_candidates(s, opt.max_maxima);
  const int nm = static_cast<int>(s.maxima.size());
  if (nm < 4) return std::nullopt;

  // The four candidates with the least summed line-fit error; adjacent sides must not be near parallel.
  // Each run's fit is made once (s.runs) and reused: the same numbers as fitting it every time.
  const double max_dot = std::cos(opt.min_angle_deg * M_PI / 180.0);
  s.runs.assign(static_cast<std::size_t>(nm * nm), QuadFitScratch::RunFit{0, 0, 0, 0, 0, 0, false});
  const auto run = [&](int a, int b) -> const QuadFitScratch::RunFit& {
    QuadFitScratch::RunFit& r = s.runs[static_cast<std::size_t>(a * nm + b)];
    if (!r.done) {
      Line l;
      r.mse = fit_run(s.cum, s.maxima[static_cast<std::size_t>(a)], s.maxima[static_cast<std::size_t>(b)], &l, &r.err);
      r.cx = l.cx, r.cy = l.cy, r.nx = l.nx, r.ny = l.ny, r.done = true;
    }
    return r;
  };
  double best = HUGE_VAL;
  int bk[4] = {0, 0, 0, 0};  // the best set's candidates (indices into s.maxima)
  for (int a = 0; a < nm - 3; ++a)
    for (int b = a + 1; b < nm - 2; ++b) {
      const auto& r01 = run(a, b);
      if (r01.mse > opt.max_line_fit_mse) continue;
      for (int c = b + 1; c < nm - 1; ++c) {
        const auto& r12 = run(b, c);
        if (r12.mse > opt.max_line_fit_mse) continue;
        if (std::abs(r01.nx * r12.nx + r01.ny * r12.ny) > max_dot) continue;
        for (int d = c + 1; d < nm; ++d) {
          const auto& r23 = run(c, d);
          if (r23.mse > opt.max_line_fit_mse) continue;
          const auto& r30 = run(d, a);
          if (r30.mse > opt.max_line_fit_mse) continue;
          const double e = r01.err + r12.err + r23.err + r30.err;
          if (e < best) best = e, bk[0] = a, bk[1] = b, bk[2] = c, bk[3] = d;
        }
      }
    }
  if (!(best / n < opt.max_line_fit_mse)) return std::nullopt;

  Line lines[4];  // the best set's sides, as fitted in the search (each passed max_line_fit_mse there)
  for (int i = 0; i < 4; ++i) {
    const auto& r = run(bk[i], bk[(i + 1) & 3]);
    lines[i] = Line{r.cx, r.cy, r.nx, r.ny};
  }
  Corners q;
  for (int i = 0; i < 4; ++i) {  // corner i: line i meets line i + 1 (n . p = n . c for both)
    const Line &a = lines[i], &b = lines[(i + 1) & 3];
    const double det = a.nx * b.ny - a.ny * b.nx;
    if (std::abs(det) < 1e-3) return std::nullopt;
    const double da = a.nx * a.cx + a.ny * a.cy, db = b.nx * b.cx + b.ny * b.cy;
    q[static_cast<std::size_t>(i)] = Eigen::Vector2d((da * b.ny - db * a.ny) / det, (a.nx * db - b.nx * da) / det);
  }

  // Area (shoelace; positive for clockwise on screen with y down), then every corner's angle and turn.
  if (0.5 * twice_signed_area(q) < min_area) return std::nullopt;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d d1 = q[(i + 1) & 3] - q[i], d2 = q[(i + 2) & 3] - q[(i + 1) & 3];
    const double den = d1.norm() * d2.norm();
    if (den == 0) return std::nullopt;
    const double c = d1.dot(d2) / den;
    if (std::abs(c) > max_dot || d1.x() * d2.y() - d1.y() * d2.x() < 0) return std::nullopt;
  }
  return q;
}

void one_side_points(std::span<const BoundaryPoint> group, bool outward, std::vector<BoundaryPoint>& out) {
  out.clear();
  if (group.empty()) return;
  const auto [xmin, xmax, ymin, ymax] = bounding_box(group);
  // In doubled coordinates: (2 p - (min + max)) . g has the sign of (p - centre) . g.
  for (const auto& p : group) {
    const int d = (2 * p.x2 - xmin - xmax) * p.gx + (2 * p.y2 - ymin - ymax) * p.gy;
    if (outward ? d > 0 : d < 0) out.push_back(p);
  }
}

Quad fitted_quad(const Corners& corners) {
  Quad q;
  q.corners = corners;
  q.segments = {-1, -1, -1, -1};
  q.observed_perimeter = perimeter(corners);
  return q;
}

std::optional<Corners> fit_outline(std::span<const BoundaryPoint> outline, const ImageF& img, const QuadFitOptions& opt,
                                   QuadFitScratch& s) {
  auto c = fit_quad(outline, img, opt, s);
  if (c && opt.outer.ring_check && !outline_has_ring(*c, img, opt.outer)) c.reset();
  return c;
}

std::optional<Corners> fit_innermost_outline(const ImageF& img, const QuadFitOptions& opt, QuadFitScratch& s) {
  const std::size_t also_outer = inner_outline_points(opt.outer, s.outer, s.side);
  if (s.side.size() < 8 || static_cast<double>(also_outer) >= 0.8 * static_cast<double>(s.side.size()))
    return std::nullopt;
  return fit_outline(s.side, img, opt, s);
}

void fit_quads(const BoundaryGroups& groups, const ImageF& img, const QuadFitOptions& opt, QuadFitScratch& s,
               std::vector<Quad>& out, std::vector<std::uint8_t>* gave_quad) {
  if (gave_quad) gave_quad->assign(groups.count(), 0);
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const auto group = groups.group(g);
    auto c = fit_quad(group, img, opt, s);
    if (!c && opt.refit_one_side && static_cast<int>(group.size()) >= 2 * std::max(opt.min_points, 4)) {
      for (const bool outward : {true, false}) {
        if (!(outward ? opt.dark_inside : opt.light_inside)) continue;
        one_side_points(group, outward, s.side);
        if (s.side.size() == group.size()) continue;  // nothing left out: the same fit again
        if ((c = fit_quad(s.side, img, opt, s))) break;
      }
    }
    const bool own_fit = c.has_value();
    if (!c && opt.tolerate_occlusion && opt.dark_inside)
      c = fit_quad_occluded(group, img, opt.min_angle_deg, 0.95 * opt.min_tag_width * opt.min_tag_width,
                            opt.occluded, s.occluded);
    // The outer outline: the quad when every fit above failed; a second candidate beside the group's
    // own fit when it left out at least outer.min_dropped of the points (that fit then saw inner edges
    // too and may have bent a side toward them; the decoder keeps whichever reads). Never beside the
    // occluded fit: an occluder's outline is outermost there, and the fit has already left it out.
    std::optional<Corners> second;
    if ((own_fit || !c) && opt.refit_outer_outline && opt.dark_inside &&
        static_cast<int>(group.size()) > std::max(opt.min_points, 4) && outline_box_admits(group, opt.outer)) {
      outer_outline_points(group, opt.outer, s.outer, s.side, static_cast<std::size_t>(std::max(opt.min_points, 4)));
      const double dropped = 1.0 - static_cast<double>(s.side.size()) / static_cast<double>(group.size());
      if (c ? dropped >= opt.outer.min_dropped : s.side.size() < group.size()) {
        const auto o = fit_outline(s.side, img, opt, s);
        if (!c) c = o;
        else if (o && max_corner_distance(*o, *c) > opt.outer.min_corner_change_px) second = o;
      }
      // Still nothing: the innermost outward outline (a square whose border ran into a darker plate).
      if (!c && opt.outer.innermost) c = fit_innermost_outline(img, opt, s);
    }
    for (const auto& corners : {c, second})
      if (corners) out.push_back(fitted_quad(*corners));
    if (gave_quad && c) (*gave_quad)[g] = 1;
  }
}

}  // namespace tagbench
