#include "detect/payload_area.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/homography.hpp"

namespace tagbench {
namespace {

// I = A x + B y + C x y + D by least squares over (x, y, I); a constant with fewer than 6 samples.
std::optional<Eigen::Vector4d> fit_bilinear_model(const std::vector<Eigen::Vector3d>& s) {
  if (s.empty()) return std::nullopt;
  Eigen::Vector4d coef = Eigen::Vector4d::Zero();
  if (s.size() < 6) {
    for (const auto& v : s) coef(3) += v.z();
    coef(3) /= static_cast<double>(s.size());
    return coef;
  }
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  Eigen::Vector4d Atb = Eigen::Vector4d::Zero();
  for (const auto& v : s) {
    const Eigen::Vector4d a(v.x(), v.y(), v.x() * v.y(), 1.0);
    AtA += a * a.transpose();
    Atb += a * v.z();
  }
  coef = AtA.ldlt().solve(Atb);
  if (!coef.allFinite()) return std::nullopt;
  return coef;
}

double model_at(const Eigen::Vector4d& m, double x, double y) { return m(0) * x + m(1) * y + m(2) * x * y + m(3); }

}  // namespace

namespace {

// The reading through any map of tag coordinates to the image (a homography, or a folded tag's two).
template <class Map>
std::optional<PayloadReading> read_area(const ImageF& img, const Map& map, int d, const PayloadAreaOptions& opt,
                                        bool keep_points) {
  if (d < 1 || d > 8 || opt.samples_per_side < 1 || !(opt.sample_extent >= 0)) return std::nullopt;
  const int n = d + 4, k = opt.samples_per_side;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  // Cell means over the grid; NaN where a sample left the image.
  std::vector<double> grid(static_cast<std::size_t>(n * n), std::nan(""));
  PayloadReading r;
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      double sum = 0;
      bool ok = true;
      for (int j = 0; j < k && ok; ++j)
        for (int i = 0; i < k && ok; ++i) {
          const double ox = ((i + 0.5) / k - 0.5) * opt.sample_extent * cell;
          const double oy = ((j + 0.5) / k - 0.5) * opt.sample_extent * cell;
          const auto v = sample_bilinear(img, map(Eigen::Vector2d(centre(gx) + ox, centre(gy) + oy)));
          if (!v) ok = false;
          else sum += *v;
        }
      if (ok) grid[static_cast<std::size_t>(gy * n + gx)] = sum / (k * k);
    }
  std::vector<Eigen::Vector3d> white, black;
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const int ring = std::min({gx, gy, n - 1 - gx, n - 1 - gy});
      const double v = grid[static_cast<std::size_t>(gy * n + gx)];
      if (ring >= 2 || std::isnan(v)) continue;
      (ring == 0 ? white : black).emplace_back(centre(gx), centre(gy), v);
      if (keep_points)
        (ring == 0 ? r.white_points : r.black_points).push_back(map(Eigen::Vector2d(centre(gx), centre(gy))));
    }
  const auto wm = fit_bilinear_model(white), bm = fit_bilinear_model(black);
  if (!wm || !bm) return std::nullopt;
  r.contrast = model_at(*wm, 0, 0) - model_at(*bm, 0, 0);
  if (!(r.contrast >= opt.min_contrast)) return std::nullopt;
  const auto at = [&](int gx, int gy) { return grid[static_cast<std::size_t>(gy * n + gx)]; };
  double sharpening = opt.sharpening;
  if (opt.small_cell_px > 0) {
    double sides = 0;  // the black square's four sides, pixels
    const Eigen::Vector2d c[4] = {map(Eigen::Vector2d(-1, -1)), map(Eigen::Vector2d(1, -1)),
                                  map(Eigen::Vector2d(1, 1)), map(Eigen::Vector2d(-1, 1))};
    for (int i = 0; i < 4; ++i) sides += (c[(i + 1) % 4] - c[i]).norm();
    if (sides / 4 / (d + 2) < opt.small_cell_px) sharpening = opt.small_cell_sharpening;
  }
  double margin = 1.0;
  Code bits = 0;
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x) {
      const int gx = x + 2, gy = y + 2;
      double v = at(gx, gy);
      if (std::isnan(v)) return std::nullopt;
      if (sharpening != 0) {
        // Neighbours are payload or black-ring cells, all inside the grid; a missing one (off the
        // image) is replaced by the cell itself, i.e. contributes nothing.
        double lap = 0;
        const int nb[4][2] = {{gx - 1, gy}, {gx + 1, gy}, {gx, gy - 1}, {gx, gy + 1}};
        for (const auto& q : nb) {
          const double u = at(q[0], q[1]);
          lap += std::isnan(u) ? 0.0 : v - u;
        }
        v += sharpening * lap;
      }
      const double tx = centre(gx), ty = centre(gy);
      const double w = model_at(*wm, tx, ty), b = model_at(*bm, tx, ty);
      const double thr = 0.5 * (w + b), half = 0.5 * (w - b);
      margin = half > 0 ? std::min(margin, std::abs(v - thr) / half) : 0.0;
      bits = (bits << 1) | (v > thr ? 1u : 0u);
      if (keep_points) r.payload_points.push_back(map(Eigen::Vector2d(tx, ty)));
    }
  r.bits = bits;
  r.margin = std::clamp(margin, 0.0, 1.0);
  return r;
}

}  // namespace

std::optional<PayloadReading> read_payload_area(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                                const PayloadAreaOptions& opt, bool keep_points) {
  return read_area(img, [&](const Eigen::Vector2d& u) { return apply_homography(H, u); }, d, opt, keep_points);
}

std::optional<PayloadReading> read_payload_area(const ImageF& img, const TagToImage& map, int d,
                                                const PayloadAreaOptions& opt, bool keep_points) {
  return read_area(img, map, d, opt, keep_points);
}

}  // namespace tagbench
