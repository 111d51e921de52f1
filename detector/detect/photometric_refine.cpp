#include "detect/photometric_refine.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/detector.hpp"

namespace tagbench {
namespace {

constexpr int kParams = 15;  // g11 g12 g13 g21 g22 g23 g31 g32 | a0 a1 a2 | b0 b1 b2 | sigma
constexpr int kSigma = 14;
using Vec = Eigen::Matrix<double, kParams, 1>;
using Mat = Eigen::Matrix<double, kParams, kParams>;

// Phi(z) and phi(z) with one exp (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7): enough for a model
// whose residuals are intensity quantisation steps.
inline void normal_cdf_pdf(double z, double& cdf, double& pdf) {
  const double e = std::exp(-0.5 * z * z);
  pdf = 0.3989422804014327 * e;
  const double x = std::abs(z) * 0.7071067811865476;
  const double t = 1 / (1 + 0.3275911 * x);
  const double erfc = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429)))) * e;
  cdf = z >= 0 ? 1 - 0.5 * erfc : 0.5 * erfc;
}

// The printed cells padded by one white cell all round (past the white ring the model assumes white),
// so the hot loop indexes without bounds checks; indices are clamped into the padding.
struct Pattern {
  explicit Pattern(const TagCells& c) : n(c.n), cell(2.0 / (c.n - 2)), padded(static_cast<std::size_t>((c.n + 2) * (c.n + 2)), 1) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) padded[static_cast<std::size_t>((y + 1) * (n + 2) + x + 1)] = c.at(y, x) ? 1 : 0;
  }
  int n;
  double cell;  // tag units per cell, 2 / (d + 2)
  std::vector<std::uint8_t> padded;
  // Grid column/row of tag coordinate u (the black square's left edge is grid line 1), clamped to
  // -1..n; truncation after a positive shift is floor() without the library call.
  int index(double u) const { return std::clamp(static_cast<int>((u + 1) / cell + 64) - 63, -1, n); }
  double line(int k) const { return -1 + (k - 1) * cell; }  // tag coordinate of grid line k
  double value(int iy, int ix) const {
    ix = std::clamp(ix, -1, n), iy = std::clamp(iy, -1, n);
    return padded[static_cast<std::size_t>((iy + 1) * (n + 2) + ix + 1)];
  }
};

// One axis of the blurred pattern at u (tag units) with blur s (tag units): the weights of the three
// columns ix-1, ix, ix+1 (the outer two absorb everything beyond them), their derivatives in u and in
// sigma (given s = sigma * k, d/dsigma = (s / sigma) d/ds).
struct Axis {
  int i0;
  std::array<double, 3> w, du, ds;
};
inline Axis axis(const Pattern& pat, double u, double s, double sigma) {
  Axis a;
  const int ix = pat.index(u);
  a.i0 = ix - 1;
  double P1, p1, P2, p2;
  const double z1 = (u - pat.line(ix)) / s, z2 = (u - pat.line(ix + 1)) / s;
  normal_cdf_pdf(z1, P1, p1);
  normal_cdf_pdf(z2, P2, p2);
  a.w = {1 - P1, P1 - P2, P2};
  a.du = {-p1 / s, (p1 - p2) / s, p2 / s};
  // d Phi(z)/d sigma = -phi(z) z / sigma
  a.ds = {p1 * z1 / sigma, (-p1 * z1 + p2 * z2) / sigma, -p2 * z2 / sigma};
  return a;
}

struct Pixel {
  double xn, yn;  // normalised image coordinates
  double value;
};

struct Problem {
  const Pattern& pat;
  const std::vector<Pixel>& px;
  double scale;  // pixels per normalised unit
};

// Model, residual and (optionally) Jacobian row at one pixel; false if the pixel maps behind the view.
inline bool evaluate(const Problem& pb, const Vec& p, const Pixel& q, double& r, Vec* J) {
  const double w = p(6) * q.xn + p(7) * q.yn + 1;
  if (!(w > 1e-9)) return false;
  const double u1 = (p(0) * q.xn + p(1) * q.yn + p(2)) / w, u2 = (p(3) * q.xn + p(4) * q.yn + p(5)) / w;
  // Tag units per image pixel along each tag axis (the gradient norms of u1 and u2 in pixels).
  const double e1 = p(0) - u1 * p(6), e2 = p(1) - u1 * p(7), f1 = p(3) - u2 * p(6), f2 = p(4) - u2 * p(7);
  const double k1 = std::sqrt(e1 * e1 + e2 * e2) / (w * pb.scale), k2 = std::sqrt(f1 * f1 + f2 * f2) / (w * pb.scale);
  const double sigma = p(kSigma);
  const Axis ax = axis(pb.pat, u1, sigma * k1, sigma), ay = axis(pb.pat, u2, sigma * k2, sigma);
  double T = 0, T1 = 0, T2 = 0, Ts = 0;
  for (int j = 0; j < 3; ++j) {  // row sums over the white cells, then the rows' weights
    double rw = 0, rdu = 0, rds = 0;
    for (int i = 0; i < 3; ++i)
      if (pb.pat.value(ay.i0 + j, ax.i0 + i) != 0) rw += ax.w[i], rdu += ax.du[i], rds += ax.ds[i];
    T += ay.w[j] * rw;
    T1 += ay.w[j] * rdu;
    T2 += ay.du[j] * rw;
    Ts += ay.w[j] * rds + ay.ds[j] * rw;
  }
  const double A = p(8) + p(9) * q.xn + p(10) * q.yn, B = p(11) + p(12) * q.xn + p(13) * q.yn;
  r = q.value - (A + B * T);
  if (J) {
    const double m1 = B * T1, m2 = B * T2;
    Vec& g = *J;
    g(0) = m1 * q.xn / w;
    g(1) = m1 * q.yn / w;
    g(2) = m1 / w;
    g(3) = m2 * q.xn / w;
    g(4) = m2 * q.yn / w;
    g(5) = m2 / w;
    g(6) = -(m1 * u1 + m2 * u2) * q.xn / w;
    g(7) = -(m1 * u1 + m2 * u2) * q.yn / w;
    g(8) = 1;
    g(9) = q.xn;
    g(10) = q.yn;
    g(11) = T;
    g(12) = T * q.xn;
    g(13) = T * q.yn;
    g(14) = B * Ts;
  }
  return true;
}

// Huber cost over the pixels, and the weighted normal equations (IRLS weights): the Jacobian's
// rows, scaled by the square roots of their weights, go into `rows` (one column per pixel) and
// J^T W J is one symmetric rank update over them (Eigen's blocked kernel: a third of the
// instructions of a per-pixel outer product).
double accumulate(const Problem& pb, const Vec& p, double huber, Eigen::Matrix<double, kParams, Eigen::Dynamic>& rows,
                  Mat& JtJ, Vec& Jtr) {
  double cost = 0;
  Jtr.setZero();
  Vec g;
  Eigen::Index n = 0;
  for (const Pixel& q : pb.px) {
    double r;
    if (!evaluate(pb, p, q, r, &g)) return INFINITY;
    const double a = std::abs(r);
    const double wt = a <= huber ? 1 : huber / a;
    cost += a <= huber ? 0.5 * r * r : huber * (a - 0.5 * huber);
    Jtr += (wt * r) * g;
    rows.col(n++) = wt == 1 ? g : std::sqrt(wt) * g;
  }
  JtJ.setZero();
  JtJ.selfadjointView<Eigen::Lower>().rankUpdate(rows.leftCols(n));
  JtJ = JtJ.selfadjointView<Eigen::Lower>();
  return cost;
}

Eigen::Vector2d map(const Eigen::Matrix3d& M, double x, double y) {
  const Eigen::Vector3d q = M * Eigen::Vector3d(x, y, 1);
  return q.head<2>() / q.z();
}

}  // namespace

std::optional<Corners> refine_corners_photometric(const ImageF& img, const TagCells& cells, const Corners& corners,
                                                  const PhotometricRefineOptions& opt) {
  if (img.empty() || cells.n < 5) return std::nullopt;
  const auto H = tag_homography(corners);
  if (!H) return std::nullopt;
  double perimeter = 0;
  for (std::size_t i = 0; i < 4; ++i) perimeter += (corners[(i + 1) % 4] - corners[i]).norm();
  const double side = perimeter / 4;
  if (!(side >= opt.min_black_square_px)) return std::nullopt;

  // Normalised image coordinates x' = (x - c) / S, for a well-conditioned G (x' -> u) with G33 = 1.
  const Eigen::Vector2d c0 = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  const double S = side / 2;
  Eigen::Matrix3d Ninv;
  Ninv << S, 0, c0.x(), 0, S, c0.y(), 0, 0, 1;
  Eigen::Matrix3d G = H->inverse() * Ninv;
  if (!(std::abs(G(2, 2)) > 1e-12)) return std::nullopt;
  G /= G(2, 2);

  const Pattern pat(cells);
  const double reach = 1 + opt.margin_cells * pat.cell;

  // The pixels near a transition of the pattern, inside the reach.
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const Eigen::Vector2d q = map(*H, sx * reach, sy * reach);
    x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
  }
  const int ix0 = std::max(0, static_cast<int>(std::ceil(x0))), ix1 = std::min(img.width - 1, static_cast<int>(std::floor(x1)));
  const int iy0 = std::max(0, static_cast<int>(std::ceil(y0))), iy1 = std::min(img.height - 1, static_cast<int>(std::floor(y1)));
  // A large tag is sampled on a coarser grid (every stride-th pixel each way) so that the transition
  // bands hold about 2 x max_pixels: the band is about a fifth of the tag's area at 8 cells across.
  const int budget = std::max(opt.max_pixels, static_cast<int>(std::min(1e7, opt.pixels_per_side_px * side)));
  const double area = std::max(0.0, (x1 - x0) * (y1 - y0));
  const int stride = std::max(1, static_cast<int>(std::sqrt(area * 0.4 / (2.0 * budget))));
  std::vector<Pixel> px;
  for (int y = iy0; y <= iy1; y += stride)
    for (int x = ix0 + (y / stride) % stride; x <= ix1; x += stride) {
      const double xn = (x - c0.x()) / S, yn = (y - c0.y()) / S;
      const double w = G(2, 0) * xn + G(2, 1) * yn + 1;
      if (!(w > 1e-9)) continue;
      const double u1 = (G(0, 0) * xn + G(0, 1) * yn + G(0, 2)) / w, u2 = (G(1, 0) * xn + G(1, 1) * yn + G(1, 2)) / w;
      if (std::abs(u1) > reach || std::abs(u2) > reach) continue;
      const double e1 = G(0, 0) - u1 * G(2, 0), e2 = G(0, 1) - u1 * G(2, 1);
      const double f1 = G(1, 0) - u2 * G(2, 0), f2 = G(1, 1) - u2 * G(2, 1);
      const double b1 = opt.band_px * std::sqrt(e1 * e1 + e2 * e2) / (w * S);
      const double b2 = opt.band_px * std::sqrt(f1 * f1 + f2 * f2) / (w * S);
      // Farther than the band from every grid line: inside one cell, no transition near.
      const double g1 = (u1 + 1) / pat.cell, g2 = (u2 + 1) / pat.cell;
      const double f1n = g1 + 64.5 - static_cast<int>(g1 + 64.5), f2n = g2 + 64.5 - static_cast<int>(g2 + 64.5);
      if (std::abs(f1n - 0.5) * pat.cell > b1 && std::abs(f2n - 0.5) * pat.cell > b2) continue;
      const double v0 = pat.value(pat.index(u2), pat.index(u1));
      bool edge = false;
      for (int j = -1; j <= 1 && !edge; ++j)
        for (int i = -1; i <= 1 && !edge; ++i)
          edge = pat.value(pat.index(u2 + j * b2), pat.index(u1 + i * b1)) != v0;
      if (edge) px.push_back({xn, yn, img.at(x, y)});
    }
  if (static_cast<int>(px.size()) < opt.min_pixels) return std::nullopt;
  if (static_cast<int>(px.size()) > budget) {  // evenly spread subsample
    const double step = static_cast<double>(px.size()) / budget;
    std::vector<Pixel> keep;
    keep.reserve(static_cast<std::size_t>(budget));
    for (int k = 0; k < budget; ++k) keep.push_back(px[static_cast<std::size_t>(k * step)]);
    px.swap(keep);
  }
  const Problem pb{pat, px, S};

  // Start: black and white levels from the pixels' 10th and 90th percentiles, no shading.
  std::vector<float> v;
  v.reserve(px.size());
  for (const Pixel& q : px) v.push_back(static_cast<float>(q.value));
  const auto lo = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 10), hi = v.begin() + static_cast<std::ptrdiff_t>(v.size() * 9 / 10);
  std::nth_element(v.begin(), lo, v.end());
  const double black = *lo;
  std::nth_element(v.begin(), hi, v.end());
  const double white = *hi;
  if (!(white - black >= opt.min_contrast)) return std::nullopt;
  Vec p;
  p << G(0, 0), G(0, 1), G(0, 2), G(1, 0), G(1, 1), G(1, 2), G(2, 0), G(2, 1), black, 0, 0, white - black, 0, 0,
      opt.initial_blur_px;
  // Huber threshold: a fraction of the contrast (so noise-free model mismatch at the edges counts in
  // full and an occluder's or glare's pixels with a bounded weight).
  const double huber = opt.huber * (white - black);
  Mat JtJ;
  Vec Jtr;
  Eigen::Matrix<double, kParams, Eigen::Dynamic> rows(kParams, static_cast<Eigen::Index>(px.size()));
  // Gauss-Newton steps, one pass over the pixels each: a step whose pass shows a higher cost than the
  // previous one is taken back and the fit stops there. The last step is taken on trust (no pass of
  // its own: the start is within a few hundredths of a pixel, where the model is nearly linear in the
  // geometry), bounded by max_corner_shift_px and the contrast check below.
  double cost = accumulate(pb, p, huber, rows, JtJ, Jtr);
  for (int it = 0; it < opt.iterations; ++it) {
    Mat A = JtJ;
    A.diagonal() += 1e-6 * JtJ.diagonal().cwiseMax(1e-12);  // a touch of damping against a flat direction
    const Vec d = A.ldlt().solve(Jtr);
    if (!d.allFinite()) return std::nullopt;
    Vec q = p + d;
    q(kSigma) = std::clamp(q(kSigma), 0.1, 8.0);
    if (it + 1 == opt.iterations) {
      p = q;
      break;
    }
    const double c = accumulate(pb, q, huber, rows, JtJ, Jtr);
    if (!(c <= cost)) break;  // p stays
    p = q, cost = c;
  }
  if (!(p(11) >= opt.min_contrast) || !(p(kSigma) <= opt.max_blur_cells * side / (cells.n - 2))) return std::nullopt;

  Eigen::Matrix3d Gr;
  Gr << p(0), p(1), p(2), p(3), p(4), p(5), p(6), p(7), 1;
  const Eigen::Matrix3d Hr = Ninv * Gr.inverse();
  Corners out;
  const std::array<Eigen::Vector2d, 4> tag{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                           Eigen::Vector2d(-1, 1)};
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = map(Hr, tag[i].x(), tag[i].y());
    if (!out[i].allFinite() || (out[i] - corners[i]).norm() > opt.max_corner_shift_px) return std::nullopt;
  }
  return out;
}

void refine_detections_photometric(std::span<Detection> detections, const ImageF& img,
                                   std::span<const TagFamily> families, const PhotometricRefineOptions& opt) {
  for (Detection& d : detections)
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      const auto c = refine_corners_photometric(img, tag_cells(f, d.id), d.corners, opt);
      const auto H = c ? tag_homography(*c) : std::nullopt;
      if (H) {
        d.corners = *c;
        d.homography = *H;
        d.center = apply_homography(*H, Eigen::Vector2d::Zero());
      }
      break;
    }
}

}  // namespace tagbench
