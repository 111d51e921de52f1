#include "detect/photometric_refine.hpp"

#include <algorithm>
#include <array>
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

struct Pattern {
  const TagCells* cells;
  double cell;  // tag units per cell, 2 / (d + 2)
  // Grid column/row of tag coordinate u (the black square's left edge is grid line 1).
  int index(double u) const { return static_cast<int>(std::floor((u + 1) / cell)) + 1; }
  double line(int k) const { return -1 + (k - 1) * cell; }  // tag coordinate of grid line k
  double value(int iy, int ix) const {
    if (ix < 0 || iy < 0 || ix >= cells->n || iy >= cells->n) return 1;  // past the white ring: white
    return cells->at(iy, ix) ? 1 : 0;
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
  const double k1 = std::hypot(p(0) - u1 * p(6), p(1) - u1 * p(7)) / (w * pb.scale);
  const double k2 = std::hypot(p(3) - u2 * p(6), p(4) - u2 * p(7)) / (w * pb.scale);
  const double sigma = p(kSigma);
  const Axis ax = axis(pb.pat, u1, sigma * k1, sigma), ay = axis(pb.pat, u2, sigma * k2, sigma);
  double T = 0, T1 = 0, T2 = 0, Ts = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const double v = pb.pat.value(ay.i0 + j, ax.i0 + i);
      if (v == 0) continue;
      T += ax.w[i] * ay.w[j];
      T1 += ax.du[i] * ay.w[j];
      T2 += ax.w[i] * ay.du[j];
      Ts += ax.ds[i] * ay.w[j] + ax.w[i] * ay.ds[j];
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

// Huber cost over the pixels; with JtJ/Jtr, also the weighted normal equations (IRLS weights).
double accumulate(const Problem& pb, const Vec& p, double huber, Mat* JtJ, Vec* Jtr) {
  double cost = 0;
  if (JtJ) {
    JtJ->setZero();
    Jtr->setZero();
  }
  Vec g;
  for (const Pixel& q : pb.px) {
    double r;
    if (!evaluate(pb, p, q, r, JtJ ? &g : nullptr)) return INFINITY;
    const double a = std::abs(r);
    const double wt = a <= huber ? 1 : huber / a;
    cost += a <= huber ? 0.5 * r * r : huber * (a - 0.5 * huber);
    if (JtJ) {
      JtJ->selfadjointView<Eigen::Upper>().rankUpdate(g, wt);
      *Jtr += wt * r * g;
    }
  }
  if (JtJ) *JtJ = JtJ->selfadjointView<Eigen::Upper>();
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

  const Pattern pat{&cells, 2.0 / (cells.n - 2)};
  const double reach = 1 + opt.margin_cells * pat.cell;

  // The pixels near a transition of the pattern, inside the reach.
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const Eigen::Vector2d q = map(*H, sx * reach, sy * reach);
    x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
  }
  const int ix0 = std::max(0, static_cast<int>(std::ceil(x0))), ix1 = std::min(img.width - 1, static_cast<int>(std::floor(x1)));
  const int iy0 = std::max(0, static_cast<int>(std::ceil(y0))), iy1 = std::min(img.height - 1, static_cast<int>(std::floor(y1)));
  std::vector<Pixel> px;
  for (int y = iy0; y <= iy1; ++y)
    for (int x = ix0; x <= ix1; ++x) {
      const double xn = (x - c0.x()) / S, yn = (y - c0.y()) / S;
      const double w = G(2, 0) * xn + G(2, 1) * yn + 1;
      if (!(w > 1e-9)) continue;
      const double u1 = (G(0, 0) * xn + G(0, 1) * yn + G(0, 2)) / w, u2 = (G(1, 0) * xn + G(1, 1) * yn + G(1, 2)) / w;
      if (std::abs(u1) > reach || std::abs(u2) > reach) continue;
      const double b1 = opt.band_px * std::hypot(G(0, 0) - u1 * G(2, 0), G(0, 1) - u1 * G(2, 1)) / (w * S);
      const double b2 = opt.band_px * std::hypot(G(1, 0) - u2 * G(2, 0), G(1, 1) - u2 * G(2, 1)) / (w * S);
      const double v0 = pat.value(pat.index(u2), pat.index(u1));
      bool edge = false;
      for (int j = -1; j <= 1 && !edge; ++j)
        for (int i = -1; i <= 1 && !edge; ++i)
          edge = pat.value(pat.index(u2 + j * b2), pat.index(u1 + i * b1)) != v0;
      if (edge) px.push_back({xn, yn, img.at(x, y)});
    }
  if (static_cast<int>(px.size()) < opt.min_pixels) return std::nullopt;
  if (static_cast<int>(px.size()) > opt.max_pixels) {  // evenly spread subsample
    const double step = static_cast<double>(px.size()) / opt.max_pixels;
    std::vector<Pixel> keep;
    keep.reserve(static_cast<std::size_t>(opt.max_pixels));
    for (int k = 0; k < opt.max_pixels; ++k) keep.push_back(px[static_cast<std::size_t>(k * step)]);
    px.swap(keep);
  }
  const Problem pb{pat, px, S};

  Vec p;
  p << G(0, 0), G(0, 1), G(0, 2), G(1, 0), G(1, 1), G(1, 2), G(2, 0), G(2, 1), 0, 0, 0, 1, 0, 0, opt.initial_blur_px;
  Mat JtJ;
  Vec Jtr;
  // The photometric parameters first (linear given the geometry), then the robust scale.
  accumulate(pb, p, INFINITY, &JtJ, &Jtr);
  {
    const Eigen::Matrix<double, 6, 6> A = JtJ.block<6, 6>(8, 8);
    const Eigen::Matrix<double, 6, 1> b = Jtr.segment<6>(8);
    const Eigen::Matrix<double, 6, 1> d = A.ldlt().solve(b);
    if (!d.allFinite()) return std::nullopt;
    p.segment<6>(8) += d;
  }
  if (!(p(11) >= opt.min_contrast)) return std::nullopt;  // white must be brighter than black
  std::vector<double> res;
  res.reserve(px.size());
  for (const Pixel& q : px) {
    double r;
    if (evaluate(pb, p, q, r, nullptr)) res.push_back(std::abs(r));
  }
  std::nth_element(res.begin(), res.begin() + static_cast<std::ptrdiff_t>(res.size() / 2), res.end());
  const double huber = std::max(opt.huber * 1.4826 * res[res.size() / 2], opt.huber_min_contrast * p(11));

  double cost = accumulate(pb, p, huber, &JtJ, &Jtr);
  const double cost0 = cost;
  double lambda = 1e-4;
  Mat JtJ_next;
  Vec Jtr_next;
  for (int it = 0, tries = 0; it < opt.iterations && tries < 3 * opt.iterations; ++tries) {
    Mat A = JtJ;
    A.diagonal() += lambda * JtJ.diagonal().cwiseMax(1e-12);
    const Vec d = A.ldlt().solve(Jtr);
    if (!d.allFinite()) return std::nullopt;
    Vec q = p + d;
    q(kSigma) = std::clamp(q(kSigma), 0.1, 8.0);
    const double c = accumulate(pb, q, huber, &JtJ_next, &Jtr_next);
    if (c < cost) {
      const double gain = cost - c;
      p = q, cost = c, JtJ = JtJ_next, Jtr = Jtr_next;
      lambda = std::max(lambda / 10, 1e-9);
      ++it;
      if (gain < 1e-10 * cost0) break;
    } else {
      lambda *= 10;
    }
  }
  if (!(cost <= cost0) || !(p(11) >= opt.min_contrast)) return std::nullopt;

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
