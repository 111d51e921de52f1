#include "detect/photometric_model.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__) && !defined(__AVX__)
#include <xmmintrin.h>
#endif

namespace tagbench::detail {

PhotometricPattern::PhotometricPattern(const TagCells& c)
    : n(c.n),
      cell(2.0 / (c.n - 2)),
      padded(static_cast<std::size_t>((c.n + 2) * (c.n + 2)), 1),
      neighbours(padded.size(), 0) {
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) padded[static_cast<std::size_t>((y + 1) * (n + 2) + x + 1)] = c.at(y, x) ? 1 : 0;
  for (int iy = -1; iy <= n; ++iy)
    for (int ix = -1; ix <= n; ++ix) {
      std::uint16_t bits = 0;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          if (white(iy - 1 + j, ix - 1 + i)) bits = static_cast<std::uint16_t>(bits | (1u << (3 * j + i)));
      neighbours[static_cast<std::size_t>((iy + 1) * (n + 2) + ix + 1)] = bits;
    }
  neighbour_weights.resize(neighbours.size());
  for (std::size_t i = 0; i < neighbours.size(); ++i)
    for (std::size_t k = 0; k < 9; ++k) neighbour_weights[i][k] = static_cast<float>((neighbours[i] >> k) & 1u);
}

namespace {

using Eigen::ArrayXf;

// Phi(z) and phi(z) with one exp (Abramowitz & Stegun 7.1.26 for erfc, |error| < 1.5e-7), every
// pixel at once. The sign of z enters as z / (|z| + tiny) (0 at z = 0, where Phi = 1/2 anyway):
// branch-free, so it vectorises.
// exp's argument is kept above -25 (phi there 1e-11, nothing next to the other terms): below it
// the products of phi would reach the subnormal range, where every operation takes a hundred cycles.
void normal_cdf_pdf(const ArrayXf& z, ArrayXf& t, ArrayXf& cdf, ArrayXf& pdf) {
  pdf = (-0.5f * z.square().min(50.0f)).exp();
  t = (1.0f + (0.3275911f * 0.70710678f) * z.abs()).inverse();
  cdf = 0.5f + 0.5f * (1.0f - t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f)))) * pdf) *
                   (z / (z.abs() + 1e-30f));
  pdf *= 0.39894228f;
}

// One axis of the blurred pattern (photometric_refine.cpp's model): the weights of the three grid
// columns ix - 1, ix, ix + 1 at u (the outer two absorb everything beyond), their derivatives in u
// and in sigma. `is` is 1 / blur in tag units; d Phi(z) / d sigma = -phi(z) z / sigma.
struct Axis {
  ArrayXf w[3], du[3], ds[3];
};
struct AxisTemps {
  ArrayXf z1, z2, P1, p1, P2, p2, t;
};
void axis(const PhotometricPattern& pat, const ArrayXf& u, const ArrayXf& is, const Eigen::ArrayXi& ix, float inv_sigma,
          AxisTemps& tmp, Axis& a) {
  const float cell = static_cast<float>(pat.cell);
  tmp.z1 = (u - ((ix - 1).cast<float>() * cell - 1.0f)) * is;
  tmp.z2 = tmp.z1 - cell * is;
  normal_cdf_pdf(tmp.z1, tmp.t, tmp.P1, tmp.p1);
  normal_cdf_pdf(tmp.z2, tmp.t, tmp.P2, tmp.p2);
  a.w[0] = 1.0f - tmp.P1;
  a.w[1] = tmp.P1 - tmp.P2;
  a.w[2] = tmp.P2;
  a.du[0] = -tmp.p1 * is;
  a.du[1] = (tmp.p1 - tmp.p2) * is;
  a.du[2] = tmp.p2 * is;
  a.ds[0] = tmp.p1 * tmp.z1 * inv_sigma;
  a.ds[1] = (tmp.p2 * tmp.z2 - tmp.p1 * tmp.z1) * inv_sigma;
  a.ds[2] = -tmp.p2 * tmp.z2 * inv_sigma;
}

}  // namespace

namespace {

#if defined(__SSE2__) && !defined(__AVX__)  // Eigen's float packet is SSE's 4 wide (AVX: 8, another order)
// K dot products of column a with columns c[0..K), Eigen's order (lower_column_dots).
template <int K>
void dots_sse(const float* a, const float* const* c, Eigen::Index m, float* out) {
  constexpr Eigen::Index P = 4;
  const Eigen::Index end2 = m / (2 * P) * (2 * P), end = m / P * P;
  float res[K];
  if (end > 0) {
    __m128 r0[K], r1[K];
    const __m128 a0 = _mm_loadu_ps(a);
    for (int k = 0; k < K; ++k) r0[k] = _mm_mul_ps(a0, _mm_loadu_ps(c[k]));
    if (end > P) {
      const __m128 a1 = _mm_loadu_ps(a + P);
      for (int k = 0; k < K; ++k) r1[k] = _mm_mul_ps(a1, _mm_loadu_ps(c[k] + P));
      for (Eigen::Index i = 2 * P; i < end2; i += 2 * P) {
        const __m128 x0 = _mm_loadu_ps(a + i), x1 = _mm_loadu_ps(a + i + P);
        for (int k = 0; k < K; ++k) {
          r0[k] = _mm_add_ps(r0[k], _mm_mul_ps(x0, _mm_loadu_ps(c[k] + i)));
          r1[k] = _mm_add_ps(r1[k], _mm_mul_ps(x1, _mm_loadu_ps(c[k] + i + P)));
        }
      }
      for (int k = 0; k < K; ++k) r0[k] = _mm_add_ps(r0[k], r1[k]);
      if (end > end2) {
        const __m128 x = _mm_loadu_ps(a + end2);
        for (int k = 0; k < K; ++k) r0[k] = _mm_add_ps(r0[k], _mm_mul_ps(x, _mm_loadu_ps(c[k] + end2)));
      }
    }
    for (int k = 0; k < K; ++k) {  // Eigen's predux: (x0 + x2) + (x1 + x3)
      const __m128 t = _mm_add_ps(r0[k], _mm_movehl_ps(r0[k], r0[k]));
      res[k] = _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
    }
    for (int k = 0; k < K; ++k)
      for (Eigen::Index i = end; i < m; ++i) res[k] = res[k] + a[i] * c[k][i];
  } else {
    for (int k = 0; k < K; ++k) {
      res[k] = a[0] * c[k][0];
      for (Eigen::Index i = 1; i < m; ++i) res[k] = res[k] + a[i] * c[k][i];
    }
  }
  for (int k = 0; k < K; ++k) out[k] = res[k];
}
#endif

}  // namespace

void lower_column_dots(const float* data, Eigen::Index stride, Eigen::Index m, int cols, float* out) {
  for (int a = 0; a < cols; ++a) {
    const float* ca = data + a * stride;
#if defined(__SSE2__) && !defined(__AVX__)
    for (int c = 0; c <= a; c += 4) {
      const float* cc[4] = {data + c * stride, data + (c + 1) * stride, data + (c + 2) * stride, data + (c + 3) * stride};
      float* o = out + a * cols + c;
      switch (std::min(4, a - c + 1)) {
        case 4: dots_sse<4>(ca, cc, m, o); break;
        case 3: dots_sse<3>(ca, cc, m, o); break;
        case 2: dots_sse<2>(ca, cc, m, o); break;
        default: dots_sse<1>(ca, cc, m, o); break;
      }
    }
#else
    for (int c = 0; c <= a; ++c)
      out[a * cols + c] = Eigen::Map<const Eigen::VectorXf>(ca, m).dot(Eigen::Map<const Eigen::VectorXf>(data + c * stride, m));
#endif
  }
}

struct PhotometricScratch::Impl {
  ArrayXf iw, u1, u2, is1, is2, T, T1, T2, Ts, B, r, sw, m1, m2;
  ArrayXf rw[3], mask[9];
  Eigen::ArrayXi ix, iy;
  AxisTemps tmp;
  Axis ax, ay;
};

PhotometricScratch::PhotometricScratch() : impl(std::make_unique<Impl>()) {}
PhotometricScratch::~PhotometricScratch() = default;

double photometric_normal_equations(const PhotometricPattern& pat, const PhotometricSamples& px, double scale,
                                    const PhotometricVec& pd, double huber, PhotometricMat& JtJ, PhotometricVec& Jtr,
                                    PhotometricScratch& scratch, bool column_dots) {
  PhotometricScratch::Impl& s = *scratch.impl;
  const Eigen::Index N = static_cast<Eigen::Index>(px.size());
  const Eigen::Map<const ArrayXf> X(px.xn.data(), N), Y(px.yn.data(), N), V(px.value.data(), N);
  std::array<float, kPhotometricParams> p;
  for (int k = 0; k < kPhotometricParams; ++k) p[static_cast<std::size_t>(k)] = static_cast<float>(pd(k));

  // The homography G (x' -> u) and the blur along each tag axis in tag units (sigma times the
  // gradient norm of u1, u2 in pixels).
  s.iw = p[6] * X + p[7] * Y + 1.0f;
  if (!(s.iw.minCoeff() > 1e-9f)) return INFINITY;
  s.iw = s.iw.inverse();
  s.u1 = (p[0] * X + p[1] * Y + p[2]) * s.iw;
  s.u2 = (p[3] * X + p[4] * Y + p[5]) * s.iw;
  const float sigma = p[kPhotometricSigma], k_scale = sigma / static_cast<float>(scale);
  s.is1 = (((p[0] - s.u1 * p[6]).square() + (p[1] - s.u1 * p[7]).square()).sqrt() * (s.iw * k_scale)).inverse();
  s.is2 = (((p[3] - s.u2 * p[6]).square() + (p[4] - s.u2 * p[7]).square()).sqrt() * (s.iw * k_scale)).inverse();
  const float inv_cell = static_cast<float>(1 / pat.cell);
  s.ix = (((s.u1 + 1.0f) * inv_cell + 64.0f).cast<int>() - 63).max(-1).min(pat.n);
  s.iy = (((s.u2 + 1.0f) * inv_cell + 64.0f).cast<int>() - 63).max(-1).min(pat.n);
  axis(pat, s.u1, s.is1, s.ix, 1.0f / sigma, s.tmp, s.ax);
  axis(pat, s.u2, s.is2, s.iy, 1.0f / sigma, s.tmp, s.ay);

  // The white cells of each pixel's 3x3 neighbourhood, as 0/1 weights (the one gather).
  for (auto& m : s.mask) m.resize(N);
  const int stride = pat.n + 2;
  for (Eigen::Index i = 0; i < N; ++i) {
    const auto& m = pat.neighbour_weights[static_cast<std::size_t>((s.iy[i] + 1) * stride + s.ix[i] + 1)];
    for (std::size_t k = 0; k < 9; ++k) s.mask[k][i] = m[k];
  }
  const auto& ax = s.ax;
  const auto& ay = s.ay;
  for (int j = 0; j < 3; ++j) s.rw[j] = s.mask[3 * j] * ax.w[0] + s.mask[3 * j + 1] * ax.w[1] + s.mask[3 * j + 2] * ax.w[2];
  const auto rdu = [&](int j) { return s.mask[3 * j] * ax.du[0] + s.mask[3 * j + 1] * ax.du[1] + s.mask[3 * j + 2] * ax.du[2]; };
  const auto rds = [&](int j) { return s.mask[3 * j] * ax.ds[0] + s.mask[3 * j + 1] * ax.ds[1] + s.mask[3 * j + 2] * ax.ds[2]; };
  s.T = ay.w[0] * s.rw[0] + ay.w[1] * s.rw[1] + ay.w[2] * s.rw[2];
  s.T1 = ay.w[0] * rdu(0) + ay.w[1] * rdu(1) + ay.w[2] * rdu(2);
  s.T2 = ay.du[0] * s.rw[0] + ay.du[1] * s.rw[1] + ay.du[2] * s.rw[2];
  s.Ts = ay.w[0] * rds(0) + ay.w[1] * rds(1) + ay.w[2] * rds(2) + ay.ds[0] * s.rw[0] + ay.ds[1] * s.rw[1] + ay.ds[2] * s.rw[2];

  // Residuals, Huber weights (IRLS: sqrt of the weight on each row), cost.
  const float h = static_cast<float>(huber);
  s.B = p[11] + p[12] * X + p[13] * Y;
  s.r = V - (p[8] + p[9] * X + p[10] * Y + s.B * s.T);
  s.sw = (h / s.r.abs().max(h)).sqrt();
  const double cost = (0.5f * s.r.abs().min(h).square() + h * (s.r.abs() - s.r.abs().min(h))).cast<double>().sum();

  // The weighted Jacobian, a column per parameter.
  s.m1 = s.B * s.T1 * s.iw * s.sw;
  s.m2 = s.B * s.T2 * s.iw * s.sw;
  auto& J = scratch.J;
  J.resize(N, kPhotometricParams);
  // Columns in single precision; the sums below over blocks of pixels, each block's in single
  // precision (SSE: four at a time) and the blocks' in double: a block's rounding (1e-6 relative)
  // stays near that of the floats themselves.
  J.col(0) = s.m1 * X;
  J.col(1) = s.m1 * Y;
  J.col(2) = s.m1;
  J.col(3) = s.m2 * X;
  J.col(4) = s.m2 * Y;
  J.col(5) = s.m2;
  J.col(6) = -(s.m1 * s.u1 + s.m2 * s.u2) * X;
  J.col(7) = -(s.m1 * s.u1 + s.m2 * s.u2) * Y;
  J.col(8) = s.sw;
  J.col(9) = s.sw * X;
  J.col(10) = s.sw * Y;
  J.col(11) = s.T * s.sw;
  J.col(12) = s.T * s.sw * X;
  J.col(13) = s.T * s.sw * Y;
  J.col(14) = s.B * s.Ts * s.sw;
  scratch.rw = (s.sw * s.r).matrix();

  constexpr Eigen::Index kBlock = 512;
  JtJ.setZero();
  Jtr.setZero();
  Eigen::Matrix<float, kPhotometricParams, kPhotometricParams> block_jtj;
  block_jtj.setZero();  // the column dot products leave the upper triangle at zero
  for (Eigen::Index b = 0; b < N; b += kBlock) {
    const Eigen::Index m = std::min(kBlock, N - b);
    const auto Jb = J.middleRows(b, m);
    if (column_dots) {
      // 120 dot products of contiguous columns (a block's columns stay in L1): about a third of the
      // general rank update's instructions at 15 columns (its packing and 8x4 kernel are built for
      // large matrices). Only the lower triangle is summed, as by the rank update.
      // (lower_column_dots: the same sums as Jb.col(a).dot(Jb.col(c)), four at a time.)
      std::array<float, kPhotometricParams * kPhotometricParams> d;
      lower_column_dots(J.data() + b, J.outerStride(), m, kPhotometricParams, d.data());
      for (int a = 0; a < kPhotometricParams; ++a)
        for (int c = 0; c <= a; ++c) block_jtj(a, c) = d[static_cast<std::size_t>(a * kPhotometricParams + c)];
    } else {
      block_jtj.setZero();
      block_jtj.selfadjointView<Eigen::Lower>().rankUpdate(Jb.transpose());
    }
    JtJ += block_jtj.cast<double>();
    Jtr += (Jb.transpose() * scratch.rw.segment(b, m)).cast<double>();
  }
  JtJ = JtJ.selfadjointView<Eigen::Lower>();
  return cost;
}

}  // namespace tagbench::detail
