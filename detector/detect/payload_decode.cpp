#include "detect/payload_decode.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "detect/homography.hpp"

namespace tagbench {
namespace {

// Least-squares fit of I = A x + B y + C x y + D (or a constant with fewer than 6 samples).
struct IntensityModel {
  Eigen::Vector4d coef = Eigen::Vector4d::Zero();  // A, B, C, D
  double at(double x, double y) const { return coef(0) * x + coef(1) * y + coef(2) * x * y + coef(3); }
};

std::optional<IntensityModel> fit_model(const std::vector<Eigen::Vector3d>& s) {  // (x, y, I)
  if (s.empty()) return std::nullopt;
  IntensityModel m;
  if (s.size() < 6) {
    double mean = 0;
    for (const auto& v : s) mean += v.z();
    m.coef(3) = mean / static_cast<double>(s.size());
    return m;
  }
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  Eigen::Vector4d Atb = Eigen::Vector4d::Zero();
  for (const auto& v : s) {
    const Eigen::Vector4d a(v.x(), v.y(), v.x() * v.y(), 1.0);
    AtA += a * a.transpose();
    Atb += a * v.z();
  }
  m.coef = AtA.ldlt().solve(Atb);
  if (!m.coef.allFinite()) return std::nullopt;
  return m;
}

}  // namespace

bool border_contrast_plausible(const ImageF& img, const std::array<Eigen::Vector2d, 4>& c, int d,
                               double min_contrast) {
  const double half_cell = 1.0 / (d + 2);  // half a ring cell, in units of the tag's half-width
  const Eigen::Vector2d centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  int good = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d m = 0.5 * (c[i] + c[(i + 1) % 4]);
    const auto vw = sample_bilinear(img, centre + (1 + half_cell) * (m - centre));
    const auto vb = sample_bilinear(img, centre + (1 - half_cell) * (m - centre));
    if (vw && vb && *vw - *vb >= min_contrast) ++good;
  }
  return good >= 3;
}

std::optional<PayloadReading> read_payload(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                           const PayloadOptions& opt, bool keep_points) {
  if (d < 1 || d > kMaxPayloadWidth) return std::nullopt;
  const int n = d + 4;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  PayloadReading r;
  std::vector<Eigen::Vector3d> white, black;
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const int ring = std::min({gx, gy, n - 1 - gx, n - 1 - gy});  // 0 white, 1 black, >= 2 payload
      if (ring >= 2) continue;
      const Eigen::Vector2d t(centre(gx), centre(gy));
      const Eigen::Vector2d p = apply_homography(H, t);
      const auto v = sample_bilinear(img, p);
      if (!v) continue;  // border cells may leave the image; the models use the rest
      (ring == 0 ? white : black).emplace_back(t.x(), t.y(), *v);
      if (keep_points) (ring == 0 ? r.white_points : r.black_points).push_back(p);
    }
  const auto wm = fit_model(white), bm = fit_model(black);
  if (!wm || !bm) return std::nullopt;
  r.contrast = wm->at(0, 0) - bm->at(0, 0);
  if (!(r.contrast >= opt.min_contrast)) return std::nullopt;
  double margin = 1.0;
  Code bits = 0;
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x) {
      const Eigen::Vector2d t(centre(x + 2), centre(y + 2));
      const Eigen::Vector2d p = apply_homography(H, t);
      const auto v = sample_bilinear(img, p);
      if (!v) return std::nullopt;
      const double w = wm->at(t.x(), t.y()), b = bm->at(t.x(), t.y());
      const double thr = 0.5 * (w + b), half = 0.5 * (w - b);
      if (half > 0) margin = std::min(margin, std::abs(*v - thr) / half);
      else margin = 0;
      bits = (bits << 1) | (*v > thr ? 1u : 0u);
      if (keep_points) r.payload_points.push_back(p);
    }
  r.bits = bits;
  r.margin = std::clamp(margin, 0.0, 1.0);
  return r;
}

}  // namespace tagbench
