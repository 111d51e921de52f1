#include "detect/pose_choice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "detect/detector.hpp"
#include "detect/payload_decode.hpp"

namespace tagbench {
namespace {

// The printed pattern (1 = white; white past the white ring) blurred by a Gaussian of `sigma` cells at
// the sample points of correlate() (samples_per_cell per cell and axis, at the sub-cells' centres),
// in correlate()'s order. Per cell, the product of the two axes' Gaussian integrals over the cells
// within 3 sigma; as the sub-cell offsets repeat in every cell, the integrals are tabulated once per
// offset (a few dozen erfc instead of tens of thousands).
std::vector<double> blurred_pattern(const TagCells& cells, int spc, double sigma) {
  const int reach = std::clamp(static_cast<int>(std::ceil(3 * sigma)), 1, 3);
  const int width = 2 * reach + 1;
  std::vector<double> w(static_cast<std::size_t>(spc * width));  // [sub-cell offset][neighbour]
  for (int i = 0; i < spc; ++i) {
    const double f = (i + 0.5) / spc;  // position within its cell, cells
    const auto phi = [&](double z) { return 0.5 * std::erfc(-z / (sigma * M_SQRT2)); };
    for (int k = -reach; k <= reach; ++k) w[static_cast<std::size_t>(i * width + k + reach)] = phi(k + 1 - f) - phi(k - f);
  }
  const auto white = [&](int cy, int cx) { return cy < 0 || cx < 0 || cy >= cells.n || cx >= cells.n || cells.at(cy, cx); };
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(cells.n * cells.n * spc * spc));
  for (int cy = 0; cy < cells.n; ++cy)
    for (int cx = 0; cx < cells.n; ++cx)
      for (int j = 0; j < spc; ++j)
        for (int i = 0; i < spc; ++i) {
          double v = 0, sum = 0;
          for (int b = -reach; b <= reach; ++b)
            for (int a = -reach; a <= reach; ++a) {
              const double ww = w[static_cast<std::size_t>(i * width + a + reach)] * w[static_cast<std::size_t>(j * width + b + reach)];
              sum += ww;
              if (white(cy + b, cx + a)) v += ww;
            }
          out.push_back(sum > 0 ? v / sum : 0.0);
        }
  return out;
}

// Pearson correlation between the pattern (blurred by `sigma` tag units, 0: sharp) and the image at
// the points `to_image` maps the pattern's sample points (tag square coordinates) to; NaN when fewer
// than half of them are inside the image.
template <class ToImage>
double correlate(const ImageF& img, const TagCells& cells, int samples_per_cell, double sigma, ToImage to_image) {
  if (cells.n < 3 || samples_per_cell < 1 || img.empty()) return NAN;
  const double cell = 2.0 / (cells.n - 2);  // the black square [-1,1]^2 is n - 2 cells across
  const std::vector<double> model = sigma > 0 ? blurred_pattern(cells, samples_per_cell, sigma / cell) : std::vector<double>{};
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  int total = 0;
  for (int cy = 0; cy < cells.n; ++cy)
    for (int cx = 0; cx < cells.n; ++cx) {
      for (int j = 0; j < samples_per_cell; ++j)
        for (int i = 0; i < samples_per_cell; ++i) {
          const std::size_t index = static_cast<std::size_t>(total++);
          const double u1 = -1 + (cx - 1 + (i + 0.5) / samples_per_cell) * cell;
          const double u2 = -1 + (cy - 1 + (j + 0.5) / samples_per_cell) * cell;
          const Eigen::Vector2d p = to_image(u1, u2);
          if (!p.allFinite()) continue;
          const std::optional<float> g = sample_bilinear(img, p);  // payload_decode.hpp's, shared
          if (!g) continue;
          const double v = sigma > 0 ? model[index] : (cells.at(cy, cx) ? 1.0 : 0.0);
          n += 1, sx += v, sy += *g, sxx += v * v, syy += double(*g) * *g, sxy += v * *g;
        }
    }
  if (2 * n < total) return NAN;
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  if (!(vx > 0) || !(vy > 0)) return NAN;
  return (sxy - sx * sy / n) / std::sqrt(vx * vy);
}

// The black square's mean side in pixels as `pose` projects it (pixels per tag unit: half of it).
double tag_side_px(const Pose& pose, const CameraIntrinsics& camera, double tag_size,
                   const std::optional<std::array<double, 5>>& distortion) {
  const std::array<std::pair<double, double>, 4> u{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  double sum = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const auto a = project_tag_point(pose, camera, tag_size, distortion, u[k].first, u[k].second);
    const auto b = project_tag_point(pose, camera, tag_size, distortion, u[(k + 1) % 4].first, u[(k + 1) % 4].second);
    sum += (a - b).norm();
  }
  return sum / 4;
}

// The pose's pattern correlation: without a lens and a model blur, through the corners' homography
// (session 7's criterion); else through the pose (and the lens), the pattern blurred by blur_px.
double correlation_of(const ImageF& img, const TagCells& cells, const Pose& pose, const CameraIntrinsics& camera,
                      double tag_size, const std::optional<std::array<double, 5>>& distortion, int samples,
                      double blur_px) {
  if (!distortion && !(blur_px > 0))
    return pattern_correlation(img, cells, project_tag_corners(pose, camera, tag_size), samples);
  return pattern_correlation_through_lens(img, cells, pose, camera, tag_size, distortion, samples, blur_px);
}

}  // namespace

double pattern_correlation(const ImageF& img, const TagCells& cells, const Corners& corners, int samples_per_cell) {
  const auto H = tag_homography(corners);
  if (!H) return NAN;
  return correlate(img, cells, samples_per_cell, 0,
                   [&](double u1, double u2) { return apply_homography(*H, Eigen::Vector2d(u1, u2)); });
}

Eigen::Vector2d project_tag_point(const Pose& pose, const CameraIntrinsics& camera, double tag_size,
                                  const std::optional<std::array<double, 5>>& distortion, double u1, double u2) {
  const Eigen::Vector3d X = pose.R * Eigen::Vector3d(u1 * tag_size / 2, u2 * tag_size / 2, 0) + pose.t;
  if (!(X.z() > 0)) return Eigen::Vector2d(NAN, NAN);
  double x = X.x() / X.z(), y = X.y() / X.z();
  if (distortion) {
    const auto& [k1, k2, p1, p2, k3] = *distortion;
    const double r2 = x * x + y * y, radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    x = xd, y = yd;
  }
  return Eigen::Vector2d(camera.fx * x + camera.cx, camera.fy * y + camera.cy);
}

double pattern_correlation_through_lens(const ImageF& img, const TagCells& cells, const Pose& pose,
                                        const CameraIntrinsics& camera, double tag_size,
                                        const std::optional<std::array<double, 5>>& distortion, int samples_per_cell,
                                        double blur_px) {
  return correlate(img, cells, samples_per_cell, blur_px * 2 / tag_side_px(pose, camera, tag_size, distortion),
                   [&](double u1, double u2) { return project_tag_point(pose, camera, tag_size, distortion, u1, u2); });
}

void choose_poses_photometric(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                              const CameraIntrinsics& camera, double tag_size, const PoseChoiceOptions& opt,
                              const std::optional<std::array<double, 5>>& distortion) {
  if (!opt.enabled || (distortion && !opt.with_lens)) return;
  for (Detection& d : detections) {
    if (!d.pose || !d.pose_alternative) continue;
    const Pose& p = d.pose->pose;
    const double cos_view = std::abs(p.R.col(2).dot(p.t.normalized()));
    const bool steep = std::acos(std::min(1.0, cos_view)) * 180 / M_PI >= opt.min_view_angle_deg;
    // The rule of the view: steep (session 7) or gentle (both solutions fit the corners within noise).
    const double max_rms = steep ? opt.max_alternative_rms_px : opt.gentle_max_alternative_rms_px;
    if (!(d.pose_alternative->reprojection_rms_px <= max_rms)) continue;
    const double gain = steep ? opt.min_correlation_gain : opt.gentle_min_correlation_gain;
    const int samples = steep ? opt.samples_per_cell : opt.gentle_samples_per_cell;
    const double blur = steep ? 0.0 : opt.gentle_model_blur_px;
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      const TagCells cells = tag_cells(f, d.id);
      const double best = correlation_of(img, cells, d.pose->pose, camera, tag_size, distortion, samples, blur);
      const double alt = correlation_of(img, cells, d.pose_alternative->pose, camera, tag_size, distortion, samples, blur);
      d.pose->pattern_correlation = best;
      d.pose_alternative->pattern_correlation = alt;
      d.pose_ambiguous = std::abs(alt - best) < opt.ambiguous_correlation_gap;  // false when either is NaN
      if (std::isfinite(alt) && (!std::isfinite(best) || alt >= best + gain)) std::swap(d.pose, d.pose_alternative);
      break;
    }
  }
}

}  // namespace tagbench
