#include "detect/pose.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace tagbench {
namespace {

Eigen::Matrix3d K_matrix(const CameraIntrinsics& K) {
  Eigen::Matrix3d M;
  M << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  return M;
}

// The nearest proper rotation (polar decomposition through the SVD).
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) = -U.col(2);
  return U * V.transpose();
}

std::array<Eigen::Vector3d, 4> tag_points(double tag_size) {
  const double h = tag_size / 2;
  return {Eigen::Vector3d(-h, -h, 0), Eigen::Vector3d(h, -h, 0), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(-h, h, 0)};
}

Eigen::Matrix<double, 8, 1> residuals(const Pose& p, const Corners& obs, const CameraIntrinsics& K, double s) {
  const Corners proj = project_tag_corners(p, K, s);
  Eigen::Matrix<double, 8, 1> r;
  for (int i = 0; i < 4; ++i) r.segment<2>(2 * i) = proj[static_cast<std::size_t>(i)] - obs[static_cast<std::size_t>(i)];
  return r;
}

Pose perturb(const Pose& p, const Eigen::Matrix<double, 6, 1>& d) {
  Pose q;
  const Eigen::Vector3d w = d.head<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d dR =
      angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  q.R = p.R * dR;  // rotation increments in the tag frame
  q.t = p.t + d.tail<3>();
  return q;
}

// Translation that best explains the normalised image points for a fixed rotation (linear least squares).
Eigen::Vector3d translation_for(const Eigen::Matrix3d& R, const std::array<Eigen::Vector2d, 4>& normalised,
                                double tag_size) {
  const auto P = tag_points(tag_size);
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d& m = normalised[static_cast<std::size_t>(i)];
    Eigen::Matrix<double, 2, 3> A;
    A << 1, 0, -m.x(), 0, 1, -m.y();
    const Eigen::Vector2d b = -A * (R * P[static_cast<std::size_t>(i)]);
    AtA += A.transpose() * A;
    Atb += A.transpose() * b;
  }
  return AtA.ldlt().solve(Atb);
}

// IPPE's two rotations from the Jacobian J of the plane -> normalised-image map at the plane
// origin, whose image is v (Collins & Bartoli 2014, section 4).
std::array<Eigen::Matrix3d, 2> ippe_rotations(const Eigen::Matrix2d& J, const Eigen::Vector2d& v) {
  Eigen::Matrix3d Rv = Eigen::Matrix3d::Identity();  // rotates the optical axis onto the ray through v
  const double t = v.norm();
  if (t > 1e-12) {
    const double s = std::sqrt(t * t + 1), costh = 1 / s, sinth = std::sqrt(1 - 1 / (s * s));
    Eigen::Matrix3d Kc;
    Kc << 0, 0, v.x(), 0, 0, v.y(), -v.x(), -v.y(), 0;
    Kc /= t;
    Rv += sinth * Kc + (1 - costh) * Kc * Kc;
  }
  Eigen::Matrix<double, 2, 3> P;
  P << 1, 0, -v.x(), 0, 1, -v.y();
  const Eigen::Matrix2d B = P * Rv.leftCols<2>();
  const Eigen::Matrix2d A = B.inverse() * J;
  // Largest singular value of A, in closed form.
  const double a = A(0, 0), b = A(0, 1), c = A(1, 0), d = A(1, 1);
  const double sq = a * a + b * b + c * c + d * d, det = a * d - b * c;
  const double gamma = std::sqrt(0.5 * (sq + std::sqrt(std::max(0.0, sq * sq - 4 * det * det))));
  const Eigen::Matrix2d R22 = A / gamma;
  Eigen::Vector2d bvec(std::sqrt(std::max(0.0, 1 - R22(0, 0) * R22(0, 0) - R22(1, 0) * R22(1, 0))),
                       std::sqrt(std::max(0.0, 1 - R22(0, 1) * R22(0, 1) - R22(1, 1) * R22(1, 1))));
  if (R22(0, 0) * R22(0, 1) + R22(1, 0) * R22(1, 1) > 0) bvec(1) = -bvec(1);  // orthogonal columns
  const Eigen::Vector3d c1(R22(0, 0), R22(1, 0), bvec(0)), c2(R22(0, 1), R22(1, 1), bvec(1));
  const Eigen::Vector3d c3 = c1.cross(c2);
  Eigen::Matrix3d Ra, Rb;
  Ra << c1, c2, c3;
  Rb << Eigen::Vector3d(c1.x(), c1.y(), -c1.z()), Eigen::Vector3d(c2.x(), c2.y(), -c2.z()),
      Eigen::Vector3d(-c3.x(), -c3.y(), c3.z());
  return {nearest_rotation(Rv * Ra), nearest_rotation(Rv * Rb)};
}

}  // namespace

bool CameraIntrinsics::valid() const {
  return std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) && fx > 0 && fy > 0;
}

Pose pose_from_homography(const Eigen::Matrix3d& H, const CameraIntrinsics& K, double tag_size) {
  // K^-1 H = s [r1 r2 t/(tag_size/2)]: the paper's equations (2)-(3) with the principal point removed.
  const Eigen::Matrix3d M = K_matrix(K).inverse() * H;
  double scale = std::sqrt(M.col(0).norm() * M.col(1).norm());
  if (M(2, 2) < 0) scale = -scale;  // the tag centre must be in front of the camera (t_z > 0)
  Eigen::Matrix3d R;
  R.col(0) = M.col(0) / scale;
  R.col(1) = M.col(1) / scale;
  R.col(2) = R.col(0).cross(R.col(1));
  Pose p;
  p.R = nearest_rotation(R);
  p.t = M.col(2) / scale * (tag_size / 2);
  return p;
}

Corners project_tag_corners(const Pose& pose, const CameraIntrinsics& K, double tag_size) {
  const auto P = tag_points(tag_size);
  Corners out;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d X = pose.R * P[i] + pose.t;
    out[i] = Eigen::Vector2d(K.fx * X.x() / X.z() + K.cx, K.fy * X.y() / X.z() + K.cy);
  }
  return out;
}

double corner_rms_error(const Pose& pose, const Corners& observed, const CameraIntrinsics& K, double tag_size) {
  return std::sqrt(residuals(pose, observed, K, tag_size).squaredNorm() / 4);
}

Pose refine_pose(const Pose& initial, const Corners& observed, const CameraIntrinsics& K, double tag_size) {
  Pose p = initial;
  double lambda = 1e-3;
  Eigen::Matrix<double, 8, 1> r = residuals(p, observed, K, tag_size);
  double cost = r.squaredNorm();
  for (int iter = 0; iter < 50 && cost > 1e-18; ++iter) {
    // Numeric Jacobian by central differences: 12 projections of 4 points, negligible next to detection.
    Eigen::Matrix<double, 8, 6> J;
    const double ht = 1e-6 * std::max(1.0, p.t.norm());
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      const double h = k < 3 ? 1e-6 : ht;
      d(k) = h;
      J.col(k) = (residuals(perturb(p, d), observed, K, tag_size) - residuals(perturb(p, -d), observed, K, tag_size)) /
                 (2 * h);
    }
    const Eigen::Matrix<double, 6, 6> JtJ = J.transpose() * J;
    const Eigen::Matrix<double, 6, 1> g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 10; ++tries) {
      Eigen::Matrix<double, 6, 6> Aug = JtJ;
      Aug.diagonal() *= 1 + lambda;
      const Eigen::Matrix<double, 6, 1> step = Aug.ldlt().solve(-g);
      const Pose q = perturb(p, step);
      const Eigen::Matrix<double, 8, 1> rq = residuals(q, observed, K, tag_size);
      if (q.t.z() > 0 && rq.squaredNorm() < cost) {
        p = q;
        r = rq;
        const double old = cost;
        cost = rq.squaredNorm();
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (old - cost < 1e-12 * old) iter = 1000;  // converged
        break;
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
  return p;
}

std::vector<PoseSolution> tag_pose_solutions(const Corners& observed, const CameraIntrinsics& K, double tag_size) {
  std::vector<PoseSolution> out;
  const auto H = tag_homography(observed);
  if (!H) return out;
  // The homography from the tag plane in metres to normalised image coordinates.
  const Eigen::Matrix3d Hn = K_matrix(K).inverse() * *H * Eigen::Vector3d(2 / tag_size, 2 / tag_size, 1).asDiagonal();
  const Eigen::Vector2d v = Eigen::Vector2d(Hn(0, 2), Hn(1, 2)) / Hn(2, 2);
  Eigen::Matrix2d J;
  J << Hn(0, 0) - Hn(2, 0) * v.x(), Hn(0, 1) - Hn(2, 1) * v.x(), Hn(1, 0) - Hn(2, 0) * v.y(),
      Hn(1, 1) - Hn(2, 1) * v.y();
  J /= Hn(2, 2);
  std::array<Eigen::Vector2d, 4> normalised;
  for (std::size_t i = 0; i < 4; ++i)
    normalised[i] = Eigen::Vector2d((observed[i].x() - K.cx) / K.fx, (observed[i].y() - K.cy) / K.fy);
  for (const Eigen::Matrix3d& R : ippe_rotations(J, v)) {
    Pose p;
    p.R = R;
    p.t = translation_for(R, normalised, tag_size);
    if (!(p.t.z() > 0)) continue;
    p = refine_pose(p, observed, K, tag_size);
    const PoseSolution s{p, corner_rms_error(p, observed, K, tag_size)};
    const bool duplicate = std::any_of(out.begin(), out.end(), [&](const PoseSolution& o) {
      return rotation_angle_deg(o.pose.R, s.pose.R) < 1e-3 && (o.pose.t - s.pose.t).norm() < 1e-9 * (1 + s.pose.t.norm());
    });
    if (!duplicate) out.push_back(s);
  }
  std::sort(out.begin(), out.end(),
            [](const PoseSolution& a, const PoseSolution& b) { return a.reprojection_rms_px < b.reprojection_rms_px; });
  return out;
}

double rotation_angle_deg(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  const double c = std::clamp(((Ra.transpose() * Rb).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

}  // namespace tagbench
