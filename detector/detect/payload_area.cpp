#include "detect/payload_area.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "detect/homography.hpp"

namespace tagbench {
namespace {

// Whether every sample of the (d+4) x (d+4) grid maps inside the image (sample_bilinear's domain)
// under H: the samples lie in a square of tag coordinates whose corners H maps in front of the camera
// (w > 0) and inside the image; w is affine, so positive over the whole square, and H maps that
// convex square onto the convex quad of those four images, inside the (convex) image rectangle.
bool whole_grid_inside(const ImageF& img, const Eigen::Matrix3d& H, int d, const PayloadAreaOptions& opt) {
  if (img.empty() || d < 1 || d > 8 || opt.samples_per_side < 1 || !(opt.sample_extent >= 0)) return false;
  const double cell = 2.0 / (d + 2), k = opt.samples_per_side;
  // The outermost samples: the white ring's cell centres, +-(1 + cell / 2), offset by (0.5 - 0.5 / k)
  // of the sampled extent; a hair more for rounding.
  const double r = 1 + 0.5 * cell + (0.5 - 0.5 / k) * opt.sample_extent * cell + 1e-9;
  for (const double sx : {-r, r})
    for (const double sy : {-r, r}) {
      const Eigen::Vector3d q = H * Eigen::Vector3d(sx, sy, 1);
      if (!(q.z() > 0)) return false;
      const double x = q.x() / q.z(), y = q.y() / q.z();
      if (!(x >= 1e-6 && y >= 1e-6 && x <= img.width - 1 - 1e-6 && y <= img.height - 1 - 1e-6)) return false;
    }
  return true;
}

#if defined(__SSE2__)
// Sum of sample_bilinear_inside(img, apply_homography(H, (u[i], v[i]))) over i < count, in order: the
// same doubles in the same operations as those calls, two samples at a time. img is at least 2 x 2
// and every point maps inside.
double homography_samples_sum(const ImageF& img, const Eigen::Matrix3d& H, const double* u, const double* v, int count) {
  double sum = 0;
  int i = 0;
  for (; i + 2 <= count; i += 2) {
    __m128d qx, qy;
    apply_homography_pair(H, _mm_loadu_pd(u + i), _mm_loadu_pd(v + i), qx, qy);
    alignas(16) float out[2];
    sample_bilinear_inside_pair(img, qx, qy, out);
    sum += out[0];
    sum += out[1];
  }
  for (; i < count; ++i) sum += sample_bilinear_inside(img, apply_homography(H, Eigen::Vector2d(u[i], v[i])));
  return sum;
}
#endif

// The cells of a reading through any map of tag coordinates to the image (a homography, or a folded
// tag's two): `grid` the (d+4)^2 cell means (NaN off the image), `payload` the d x d sharpened values.
// `inside`: the caller knows every sample lands inside the image (whole_grid_inside), so none is
// tested; the values are the same as with the test. `homography`: map is apply_homography with it (then, with inside, the samples are taken two at a
// time: homography_samples_sum, the same numbers).
template <class Map>
bool area_cells(const ImageF& img, const Map& map, int d, const PayloadAreaOptions& opt, std::vector<double>& grid,
                std::vector<double>& payload, bool inside = false, const Eigen::Matrix3d* homography = nullptr) {
  if (d < 1 || d > 8 || opt.samples_per_side < 1 || !(opt.sample_extent >= 0)) return false;
  const int n = d + 4, k = opt.samples_per_side;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  // Cell means over the grid; NaN where a sample left the image.
  grid.assign(static_cast<std::size_t>(n * n), std::nan(""));
  // The samples' offsets within a cell, the same for every cell: computed once (up to 16 a side;
  // the same expression, so the same numbers, as computing them per sample).
  constexpr int kMaxOffsets = 16;
  std::array<double, kMaxOffsets> offsets{};
  const auto offset = [&](int i) { return ((i + 0.5) / k - 0.5) * opt.sample_extent * cell; };
  for (int i = 0; i < std::min(k, kMaxOffsets); ++i) offsets[static_cast<std::size_t>(i)] = offset(i);
  const auto offset_of = [&](int i) { return i < kMaxOffsets ? offsets[static_cast<std::size_t>(i)] : offset(i); };
#if defined(__SSE2__)
  if (homography && inside && k <= kMaxOffsets && img.width >= 2 && img.height >= 2) {
    std::array<double, kMaxOffsets * kMaxOffsets> u, v;  // a cell's sample points, in the loop's order
    for (int gy = 0; gy < n; ++gy)
      for (int gx = 0; gx < n; ++gx) {
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) {
            u[static_cast<std::size_t>(j * k + i)] = centre(gx) + offsets[static_cast<std::size_t>(i)];
            v[static_cast<std::size_t>(j * k + i)] = centre(gy) + offsets[static_cast<std::size_t>(j)];
          }
        grid[static_cast<std::size_t>(gy * n + gx)] = homography_samples_sum(img, *homography, u.data(), v.data(), k * k) / (k * k);
      }
  } else
#endif
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      double sum = 0;
      bool ok = true;
      for (int j = 0; j < k && ok; ++j)
        for (int i = 0; i < k && ok; ++i) {
          const double ox = offset_of(i), oy = offset_of(j);
          const Eigen::Vector2d p = map(Eigen::Vector2d(centre(gx) + ox, centre(gy) + oy));
          if (inside) {
            sum += sample_bilinear_inside(img, p);
            continue;
          }
          const auto v = sample_bilinear(img, p);
          if (!v) ok = false;
          else sum += *v;
        }
      if (ok) grid[static_cast<std::size_t>(gy * n + gx)] = sum / (k * k);
    }
  const auto at = [&](int gx, int gy) { return grid[static_cast<std::size_t>(gy * n + gx)]; };
  double sharpening = opt.sharpening;
  if (opt.small_cell_px > 0) {
    // The black square's corners through the homography; its perimeter in pixels.
    const Corners c = {map(Eigen::Vector2d(-1, -1)), map(Eigen::Vector2d(1, -1)), map(Eigen::Vector2d(1, 1)),
                       map(Eigen::Vector2d(-1, 1))};
    if (perimeter(c) / 4 / (d + 2) < opt.small_cell_px) sharpening = opt.small_cell_sharpening;
  }
  payload.resize(static_cast<std::size_t>(d * d));
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
  return true;
}

// The ring models' reading (read_payload_area).
template <class Map>
std::optional<PayloadReading> read_area(const ImageF& img, const Map& map, int d, const PayloadAreaOptions& opt,
                                        bool keep_points, bool inside = false, const Eigen::Matrix3d* homography = nullptr) {
  std::vector<double> grid, payload;
  if (!area_cells(img, map, d, opt, grid, payload, inside, homography)) return std::nullopt;
  auto r = decide_cells(grid, payload, d, opt.min_contrast);
  if (r && keep_points) add_sample_points(grid, d, map, *r);
  return r;
}

// The 2-means split of the payload values (Lloyd's iterations from the midpoint of the extremes):
// the threshold and the two means, or nothing when one side empties.
struct Split {
  double threshold, low, high;
};
std::optional<Split> two_means(std::span<const double> v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  double t = 0.5 * (*lo + *hi);
  Split s{t, *lo, *hi};
  for (int it = 0; it < 32; ++it) {
    double a = 0, b = 0;
    int na = 0, nb = 0;
    for (const double x : v) {
      if (x > t) a += x, ++na;
      else b += x, ++nb;
    }
    if (na == 0 || nb == 0) return std::nullopt;
    s = Split{0.5 * (a / na + b / nb), b / nb, a / na};
    if (s.threshold == t) break;
    t = s.threshold;
  }
  return s;
}

}  // namespace

std::optional<PayloadReading> read_payload_self_threshold(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                                          const PayloadAreaOptions& opt) {
  std::vector<double> grid, payload;
  if (!area_cells(img, [&](const Eigen::Vector2d& u) { return apply_homography(H, u); }, d, opt, grid, payload))
    return std::nullopt;
  for (const double v : payload)
    if (std::isnan(v)) return std::nullopt;
  const auto split = two_means(payload);
  if (!split || !(split->high - split->low >= opt.min_contrast)) return std::nullopt;
  const int n = d + 4;
  int ring = 0, light = 0;  // the black ring's cells with a value, and those above the threshold
  for (int gy = 1; gy < n - 1; ++gy)
    for (int gx = 1; gx < n - 1; ++gx) {
      const double v = grid[static_cast<std::size_t>(gy * n + gx)];
      if (std::min({gx, gy, n - 1 - gx, n - 1 - gy}) != 1 || std::isnan(v)) continue;
      ++ring;
      light += v > split->threshold ? 1 : 0;
    }
  if (ring == 0 || light > opt.self_threshold.max_light_black_ring * ring) return std::nullopt;
  PayloadReading r;
  r.contrast = split->high - split->low;
  const double half = 0.5 * r.contrast;
  double margin = 1.0;
  r.confidence.resize(payload.size());
  for (std::size_t i = 0; i < payload.size(); ++i) {
    const double c = (payload[i] - split->threshold) / half;
    r.confidence[i] = static_cast<float>(c);
    margin = std::min(margin, std::abs(c));
    r.bits = (r.bits << 1) | (c > 0 ? 1u : 0u);
  }
  r.margin = std::clamp(margin, 0.0, 1.0);
  return r;
}

std::optional<PayloadReading> read_payload_area(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                                const PayloadAreaOptions& opt, bool keep_points) {
  return read_area(img, [&](const Eigen::Vector2d& u) { return apply_homography(H, u); }, d, opt, keep_points,
                   whole_grid_inside(img, H, d, opt), &H);
}

std::optional<PayloadReading> read_payload_area(const ImageF& img, const TagToImage& map, int d,
                                                const PayloadAreaOptions& opt, bool keep_points) {
  return read_area(img, map, d, opt, keep_points);
}

}  // namespace tagbench
