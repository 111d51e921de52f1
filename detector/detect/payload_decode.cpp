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

bool border_contrast_plausible_with_slack(const ImageF& img, const std::array<Eigen::Vector2d, 4>& c, int d,
                                          double min_contrast, int min_sides) {
  const double cell = 2.0 / (d + 2);  // a ring cell, in units of the tag's half-width
  const Eigen::Vector2d centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  int good = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d m = 0.5 * (c[i] + c[(i + 1) % 4]) - centre;
    float lightest_out = -HUGE_VALF, darkest_in = HUGE_VALF;
    bool inside = true;
    for (const double f : {0.25, 0.5, 0.75, 1.0}) {
      const auto v = sample_bilinear(img, centre + (1 + f * cell) * m);
      inside = inside && v.has_value();
      if (v) lightest_out = std::max(lightest_out, *v);
    }
    for (const double f : {0.25, 0.5, 0.75}) {
      const auto v = sample_bilinear(img, centre + (1 - f * cell) * m);
      inside = inside && v.has_value();
      if (v) darkest_in = std::min(darkest_in, *v);
    }
    if (inside && lightest_out - darkest_in >= min_contrast) ++good;
  }
  return good >= min_sides;
}

bool border_worth_refining(const ImageF& img, const std::array<Eigen::Vector2d, 4>& corners, int d,
                           double min_contrast, int slack_sides) {
  return border_contrast_plausible(img, corners, d, min_contrast) ||
         (slack_sides > 0 && border_contrast_plausible_with_slack(img, corners, d, min_contrast, slack_sides));
}

std::optional<PayloadReading> decide_cells(std::span<const double> grid, std::span<const double> payload, int d,
                                           double min_contrast) {
  const int n = d + 4;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  std::vector<Eigen::Vector3d> white, black;
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const int ring = std::min({gx, gy, n - 1 - gx, n - 1 - gy});  // 0 white, 1 black, >= 2 payload
      const double v = grid[static_cast<std::size_t>(gy * n + gx)];
      if (ring >= 2 || std::isnan(v)) continue;  // border cells may leave the image; the models use the rest
      (ring == 0 ? white : black).emplace_back(centre(gx), centre(gy), v);
    }
  const auto wm = fit_model(white), bm = fit_model(black);
  if (!wm || !bm) return std::nullopt;
  PayloadReading r;
  r.contrast = wm->at(0, 0) - bm->at(0, 0);
  if (!(r.contrast >= min_contrast)) return std::nullopt;
  double margin = 1.0;
  Code bits = 0;
  r.confidence.resize(static_cast<std::size_t>(d * d));
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x) {
      const double v = payload[static_cast<std::size_t>(y * d + x)];
      if (std::isnan(v)) return std::nullopt;
      const double tx = centre(x + 2), ty = centre(y + 2);
      const double w = wm->at(tx, ty), b = bm->at(tx, ty);
      const double thr = 0.5 * (w + b), half = 0.5 * (w - b);
      margin = half > 0 ? std::min(margin, std::abs(v - thr) / half) : 0.0;
      r.confidence[static_cast<std::size_t>(y * d + x)] = half > 0 ? static_cast<float>((v - thr) / half) : 0.0f;
      bits = (bits << 1) | (v > thr ? 1u : 0u);
    }
  r.bits = bits;
  r.margin = std::clamp(margin, 0.0, 1.0);
  return r;
}

std::optional<PayloadReading> read_payload(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                           const PayloadOptions& opt, bool keep_points) {
  if (d < 1 || d > kMaxPayloadWidth) return std::nullopt;
  const int n = d + 4;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  const auto map = [&](const Eigen::Vector2d& t) { return apply_homography(H, t); };
  // One bilinear sample at each cell's centre (NaN off the image).
  std::vector<double> grid(static_cast<std::size_t>(n * n)), payload(static_cast<std::size_t>(d * d));
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const auto v = sample_bilinear(img, map(Eigen::Vector2d(centre(gx), centre(gy))));
      grid[static_cast<std::size_t>(gy * n + gx)] = v ? *v : std::nan("");
    }
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x)
      payload[static_cast<std::size_t>(y * d + x)] = grid[static_cast<std::size_t>((y + 2) * n + x + 2)];
  auto r = decide_cells(grid, payload, d, opt.min_contrast);
  if (r && keep_points) add_sample_points(grid, d, map, *r);
  return r;
}

}  // namespace tagbench
