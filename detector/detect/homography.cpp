#include "detect/homography.hpp"

#include <cmath>

#include <Eigen/Dense>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace tagbench {
namespace {

// Similarity moving the points' centroid to the origin and their mean distance to sqrt(2).
std::optional<Eigen::Matrix3d> normaliser(std::span<const Eigen::Vector2d> pts) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  double mean = 0;
  for (const auto& p : pts) mean += (p - c).norm();
  mean /= static_cast<double>(pts.size());
  if (!(mean > 1e-12) || !std::isfinite(mean)) return std::nullopt;
  const double s = std::sqrt(2.0) / mean;
  Eigen::Matrix3d T;
  T << s, 0, -s * c.x(), 0, s, -s * c.y(), 0, 0, 1;
  return T;
}

// Undoes the normalisations and scales H to unit Frobenius norm with H(2,2) >= 0.
std::optional<Eigen::Matrix3d> denormalise(const Eigen::Matrix3d& Hn, const Eigen::Matrix3d& Tf,
                                           const Eigen::Matrix3d& Tt) {
  Eigen::Matrix3d H = Tt.inverse() * Hn * Tf;
  const double norm = H.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return std::nullopt;
  H /= norm;
  if (H(2, 2) < 0) H = -H;
  return H;
}

}  // namespace

const Corners& tag_square_corners() {
  static const Corners c = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                            Eigen::Vector2d(-1, 1)};
  return c;
}

std::optional<Eigen::Matrix3d> homography_dlt(std::span<const Eigen::Vector2d> from,
                                              std::span<const Eigen::Vector2d> to) {
  const std::size_t n = from.size();
  if (n < 4 || to.size() != n) return std::nullopt;
  const auto Tf = normaliser(from), Tt = normaliser(to);
  if (!Tf || !Tt) return std::nullopt;
  if (n == 4) {
    // Exactly determined (the per-quad case, thousands of times a frame): fix h22 = 1 and solve the
    // 8x8 system in fixed size, ~20x faster than the SVD; h22 = 0 only if the first plane point's
    // centroid maps to infinity, impossible for a quad seen in the image.
    Eigen::Matrix<double, 8, 8> M;
    Eigen::Matrix<double, 8, 1> b;
    for (std::size_t i = 0; i < 4; ++i) {
      const Eigen::Vector3d p = *Tf * from[i].homogeneous(), q = *Tt * to[i].homogeneous();
      const double x = p.x(), y = p.y(), u = q.x(), v = q.y();
      const auto r = static_cast<Eigen::Index>(2 * i);
      M.row(r) << x, y, 1, 0, 0, 0, -u * x, -u * y;
      M.row(r + 1) << 0, 0, 0, x, y, 1, -v * x, -v * y;
      b(r) = u;
      b(r + 1) = v;
    }
    const Eigen::FullPivLU<Eigen::Matrix<double, 8, 8>> lu(M);
    if (lu.rank() < 8 || std::abs(lu.determinant()) < 1e-12) return std::nullopt;  // collinear or repeated points
    const Eigen::Matrix<double, 8, 1> h = lu.solve(b);
    Eigen::Matrix3d Hn;
    Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), 1.0;
    return denormalise(Hn, *Tf, *Tt);
  }
  Eigen::MatrixXd A(2 * n, 9);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = *Tf * from[i].homogeneous(), q = *Tt * to[i].homogeneous();
    const double x = p.x(), y = p.y(), u = q.x(), v = q.y();
    const auto r = static_cast<Eigen::Index>(2 * i);
    A.row(r) << 0, 0, 0, -x, -y, -1, v * x, v * y, v;
    A.row(r + 1) << x, y, 1, 0, 0, 0, -u * x, -u * y, -u;
  }
  // The null vector: the right singular vector of the smallest singular value.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  // Degenerate configurations (e.g. 3 collinear points) leave a null space of dimension > 1.
  if (n == 4 && sv(7) < 1e-9 * sv(0)) return std::nullopt;
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d Hn;
  Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  return denormalise(Hn, *Tf, *Tt);
}

std::optional<Eigen::Matrix3d> tag_homography(const Corners& image_corners) {
  return homography_dlt(tag_square_corners(), image_corners);
}

Corners printed_corners(const Corners& quad, int rotation) {
  Corners c;
  for (int i = 0; i < 4; ++i) c[static_cast<std::size_t>(i)] = quad[static_cast<std::size_t>((i + rotation) % 4)];
  return c;
}

std::pair<double, double> side_length_range(const Corners& quad) {
  double shortest = HUGE_VAL, longest = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const double len = (quad[(i + 1) % 4] - quad[i]).norm();
    shortest = std::min(shortest, len), longest = std::max(longest, len);
  }
  return {shortest, longest};
}

bool inside_quad(const Corners& q, const Eigen::Vector2d& p) {
  QuadRowTest t(q);
  t.row(p.y());
  return t.contains(p.x());
}

}  // namespace tagbench
