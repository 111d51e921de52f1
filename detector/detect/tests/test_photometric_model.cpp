#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>
#include <random>

#include <Eigen/Dense>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/photometric_model.hpp"

namespace test_photometric_model {

using namespace tagbench;
using namespace tagbench::detail;

namespace {

// The model of photometric_refine.hpp written out pixel by pixel in double precision (how the
// refinement first computed it): the reference the vectorised single-precision kernel must match.
void reference_cdf_pdf(double z, double& cdf, double& pdf) {
  pdf = std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI);
  cdf = 0.5 * std::erfc(-z / std::sqrt(2.0));
}

struct RefAxis {
  int i0;
  double w[3], du[3], ds[3];
};

RefAxis reference_axis(const PhotometricPattern& pat, double u, double s, double sigma) {
  RefAxis a;
  const int ix = pat.index(u);
  a.i0 = ix - 1;
  double P1, p1, P2, p2;
  const double z1 = (u - pat.line(ix)) / s, z2 = (u - pat.line(ix + 1)) / s;
  reference_cdf_pdf(z1, P1, p1);
  reference_cdf_pdf(z2, P2, p2);
  a.w[0] = 1 - P1, a.w[1] = P1 - P2, a.w[2] = P2;
  a.du[0] = -p1 / s, a.du[1] = (p1 - p2) / s, a.du[2] = p2 / s;
  a.ds[0] = p1 * z1 / sigma, a.ds[1] = (-p1 * z1 + p2 * z2) / sigma, a.ds[2] = -p2 * z2 / sigma;
  return a;
}

double reference(const PhotometricPattern& pat, const PhotometricSamples& px, double scale, const PhotometricVec& p,
                 double huber, PhotometricMat& JtJ, PhotometricVec& Jtr) {
  JtJ.setZero();
  Jtr.setZero();
  double cost = 0;
  for (std::size_t k = 0; k < px.size(); ++k) {
    const double xn = px.xn[k], yn = px.yn[k];
    const double w = p(6) * xn + p(7) * yn + 1;
    if (!(w > 1e-9)) return INFINITY;
    const double u1 = (p(0) * xn + p(1) * yn + p(2)) / w, u2 = (p(3) * xn + p(4) * yn + p(5)) / w;
    const double e1 = p(0) - u1 * p(6), e2 = p(1) - u1 * p(7), f1 = p(3) - u2 * p(6), f2 = p(4) - u2 * p(7);
    const double k1 = std::hypot(e1, e2) / (w * scale), k2 = std::hypot(f1, f2) / (w * scale);
    const double sigma = p(kPhotometricSigma);
    const RefAxis ax = reference_axis(pat, u1, sigma * k1, sigma), ay = reference_axis(pat, u2, sigma * k2, sigma);
    double T = 0, T1 = 0, T2 = 0, Ts = 0;
    for (int j = 0; j < 3; ++j) {
      double rw = 0, rdu = 0, rds = 0;
      for (int i = 0; i < 3; ++i)
        if (pat.white(ay.i0 + j, ax.i0 + i)) rw += ax.w[i], rdu += ax.du[i], rds += ax.ds[i];
      T += ay.w[j] * rw, T1 += ay.w[j] * rdu, T2 += ay.du[j] * rw, Ts += ay.w[j] * rds + ay.ds[j] * rw;
    }
    const double A = p(8) + p(9) * xn + p(10) * yn, B = p(11) + p(12) * xn + p(13) * yn;
    const double r = px.value[k] - (A + B * T);
    const double m1 = B * T1, m2 = B * T2;
    PhotometricVec g;
    g << m1 * xn / w, m1 * yn / w, m1 / w, m2 * xn / w, m2 * yn / w, m2 / w, -(m1 * u1 + m2 * u2) * xn / w,
        -(m1 * u1 + m2 * u2) * yn / w, 1, xn, yn, T, T * xn, T * yn, B * Ts;
    const double a = std::abs(r), wt = a <= huber ? 1 : huber / a;
    cost += a <= huber ? 0.5 * r * r : huber * (a - 0.5 * huber);
    Jtr += wt * r * g;
    JtJ += wt * g * g.transpose();
  }
  return cost;
}

// A tag seen slightly in perspective, pixels spread over it and its white ring, intensities from a
// shaded, blurred rendering plus noise (so residuals of both signs, some beyond the Huber threshold).
struct Problem {
  PhotometricPattern pat{tag_cells(builtin_family("36h11"), 17)};
  PhotometricSamples px;
  PhotometricVec p;
};

Problem make_problem(std::uint32_t seed, int count) {
  Problem pb;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-1.3, 1.3), noise(-0.08, 0.08);
  pb.p << 1.02, 0.05, 0.01, -0.04, 0.97, -0.02, 0.03, -0.02, 0.12, 0.01, -0.02, 0.7, 0.02, 0.01, 0.9;
  for (int k = 0; k < count; ++k) {
    const double x = pos(rng), y = pos(rng);
    pb.px.xn.push_back(static_cast<float>(x));
    pb.px.yn.push_back(static_cast<float>(y));
    // Roughly the model's own value (the white ring or a payload cell) with noise.
    const double u = x, v = y;
    const bool white = pb.pat.white(pb.pat.index(v), pb.pat.index(u));
    pb.px.value.push_back(static_cast<float>(0.12 + (white ? 0.7 : 0) + noise(rng)));
  }
  return pb;
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST(PhotometricModel, NeighbourBitsAreTheClampedCells) {
  const PhotometricPattern pat(tag_cells(builtin_family("36h11"), 5));
  for (int iy = -1; iy <= pat.n; ++iy)
    for (int ix = -1; ix <= pat.n; ++ix) {
      const unsigned bits = pat.neighbours[static_cast<std::size_t>((iy + 1) * (pat.n + 2) + ix + 1)];
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          EXPECT_EQ((bits >> (3 * j + i)) & 1u, pat.white(iy - 1 + j, ix - 1 + i) ? 1u : 0u) << iy << " " << ix;
    }
  EXPECT_TRUE(pat.white(0, 0));   // the white ring
  EXPECT_FALSE(pat.white(1, 1));  // the black ring
  EXPECT_TRUE(pat.white(-1, 3));  // the padding
}

// The single-precision kernel gives the double reference's cost and normal equations to 1e-4
// (the Gauss-Newton step then agrees to the same order); pixel counts around the block size; J^T W J
// by Eigen's rank update and by column dot products (PhotometricRefineOptions::column_dot_sums).
TEST(PhotometricModel, NormalEquationsMatchTheDoubleReference) {
  for (const bool dots : {false, true})
  for (const int count : {50, 511, 1500}) {
    SCOPED_TRACE(dots ? "column dot products" : "rank update");
    const Problem pb = make_problem(static_cast<std::uint32_t>(count), count);
    const double scale = 20, huber = 0.05;
    PhotometricMat JtJ, JtJ_ref;
    PhotometricVec Jtr, Jtr_ref;
    PhotometricScratch scratch;
    const double cost = photometric_normal_equations(pb.pat, pb.px, scale, pb.p, huber, JtJ, Jtr, scratch, dots);
    const double cost_ref = reference(pb.pat, pb.px, scale, pb.p, huber, JtJ_ref, Jtr_ref);
    EXPECT_NEAR(cost, cost_ref, 1e-4 * cost_ref) << count;
    EXPECT_LT(rel(JtJ, JtJ_ref), 1e-4) << count;
    EXPECT_LT(rel(Jtr, Jtr_ref), 1e-4) << count;
    const PhotometricVec d = JtJ.ldlt().solve(Jtr), d_ref = JtJ_ref.ldlt().solve(Jtr_ref);
    EXPECT_LT(rel(d, d_ref), 1e-3) << count;
    // The same scratch again (smaller problem): nothing left over from the larger one.
    const Problem small = make_problem(99, 40);
    const double c2 = photometric_normal_equations(small.pat, small.px, scale, small.p, huber, JtJ, Jtr, scratch, dots);
    EXPECT_NEAR(c2, reference(small.pat, small.px, scale, small.p, huber, JtJ_ref, Jtr_ref), 1e-4 * c2);
  }
}

TEST(PhotometricModel, PixelBehindTheViewGivesInfinity) {
  Problem pb = make_problem(3, 100);
  pb.p(6) = -2;  // w = 1 - 2 x' <= 0 for x' >= 0.5
  PhotometricMat JtJ;
  PhotometricVec Jtr;
  PhotometricScratch scratch;
  EXPECT_TRUE(std::isinf(photometric_normal_equations(pb.pat, pb.px, 20, pb.p, 0.05, JtJ, Jtr, scratch)));
}

// lower_column_dots must give Eigen's own dot products bit for bit (the refinement's corners depend
// on the summation order): every block length from 1 to 1100 and odd column strides, random values
// of mixed sign and magnitude.
TEST(PhotometricModel, LowerColumnDotsAreEigensDotsBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1), e(-6, 6);
  constexpr int kCols = kPhotometricParams;
  for (Eigen::Index m = 1; m <= 1100; m += (m < 40 ? 1 : 37)) {
    for (const Eigen::Index pad : {0, 1, 3}) {
      const Eigen::Index stride = m + pad;
      std::vector<float> data(static_cast<std::size_t>(stride * kCols));
      for (float& v : data) v = u(rng) * std::exp2(e(rng));
      std::vector<float> out(kCols * kCols, 0.0f);
      lower_column_dots(data.data(), stride, m, kCols, out.data());
      for (int a = 0; a < kCols; ++a)
        for (int c = 0; c <= a; ++c) {
          const Eigen::Map<const Eigen::VectorXf> ca(data.data() + a * stride, m), cc(data.data() + c * stride, m);
          const float want = ca.dot(cc);
          ASSERT_EQ(std::memcmp(&want, &out[static_cast<std::size_t>(a * kCols + c)], sizeof(float)), 0)
              << "m " << m << " stride " << stride << " a " << a << " c " << c << ": " << want << " vs "
              << out[static_cast<std::size_t>(a * kCols + c)];
        }
    }
  }
}

}  // namespace test_photometric_model
