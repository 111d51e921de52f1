#include "detect/payload_area.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/homography.hpp"

namespace tagbench {
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
  const auto at = [&](int gx, int gy) { return grid[static_cast<std::size_t>(gy * n + gx)]; };
  double sharpening = opt.sharpening;
  if (opt.small_cell_px > 0) {
    double sides = 0;  // the black square's four sides, pixels
    const Eigen::Vector2d c[4] = {map(Eigen::Vector2d(-1, -1)), map(Eigen::Vector2d(1, -1)),
                                  map(Eigen::Vector2d(1, 1)), map(Eigen::Vector2d(-1, 1))};
    for (int i = 0; i < 4; ++i) sides += (c[(i + 1) % 4] - c[i]).norm();
    if (sides / 4 / (d + 2) < opt.small_cell_px) sharpening = opt.small_cell_sharpening;
  }
  std::vector<double> payload(static_cast<std::size_t>(d * d));
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x) {
      const int gx = x + 2, gy = y + 2;
      double v = at(gx, gy);
      if (sharpening != 0 && !std::isnan(v)) {
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
      payload[static_cast<std::size_t>(y * d + x)] = v;
    }
  auto r = decide_cells(grid, payload, d, opt.min_contrast);
  if (r && keep_points) add_sample_points(grid, d, map, *r);
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
