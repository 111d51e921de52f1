#include "detect/pose_choice.hpp"

#include <cmath>
#include <utility>

#include "detect/detector.hpp"

namespace tagbench {

double pattern_correlation(const ImageF& img, const TagCells& cells, const Corners& corners, int samples_per_cell) {
  const auto H = tag_homography(corners);
  if (!H || cells.n < 3 || samples_per_cell < 1 || img.empty()) return NAN;
  const double cell = 2.0 / (cells.n - 2);  // the black square [-1,1]^2 is n - 2 cells across
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  int total = 0;
  for (int cy = 0; cy < cells.n; ++cy)
    for (int cx = 0; cx < cells.n; ++cx) {
      const double v = cells.at(cy, cx) ? 1.0 : 0.0;
      for (int j = 0; j < samples_per_cell; ++j)
        for (int i = 0; i < samples_per_cell; ++i) {
          ++total;
          const double u1 = -1 + (cx - 1 + (i + 0.5) / samples_per_cell) * cell;
          const double u2 = -1 + (cy - 1 + (j + 0.5) / samples_per_cell) * cell;
          const Eigen::Vector2d p = apply_homography(*H, Eigen::Vector2d(u1, u2));
          if (!p.allFinite() || p.x() < 0 || p.y() < 0 || p.x() > img.width - 1 || p.y() > img.height - 1) continue;
          const int x0 = std::min(static_cast<int>(p.x()), img.width - 2), y0 = std::min(static_cast<int>(p.y()), img.height - 2);
          const double ax = p.x() - x0, ay = p.y() - y0;
          const double g = (img.at(x0, y0) * (1 - ax) + img.at(x0 + 1, y0) * ax) * (1 - ay) +
                           (img.at(x0, y0 + 1) * (1 - ax) + img.at(x0 + 1, y0 + 1) * ax) * ay;
          n += 1, sx += v, sy += g, sxx += v * v, syy += g * g, sxy += v * g;
        }
    }
  if (2 * n < total) return NAN;
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  if (!(vx > 0) || !(vy > 0)) return NAN;
  return (sxy - sx * sy / n) / std::sqrt(vx * vy);
}

void choose_poses_photometric(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                              const CameraIntrinsics& camera, double tag_size, const PoseChoiceOptions& opt) {
  if (!opt.enabled) return;
  for (Detection& d : detections) {
    if (!d.pose || !d.pose_alternative || !(d.pose_alternative->reprojection_rms_px <= opt.max_alternative_rms_px))
      continue;
    const Pose& p = d.pose->pose;
    const double cos_view = std::abs(p.R.col(2).dot(p.t.normalized()));
    if (!(std::acos(std::min(1.0, cos_view)) * 180 / M_PI >= opt.min_view_angle_deg)) continue;
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      const TagCells cells = tag_cells(f, d.id);
      const double best = pattern_correlation(img, cells, project_tag_corners(d.pose->pose, camera, tag_size), opt.samples_per_cell);
      const double alt =
          pattern_correlation(img, cells, project_tag_corners(d.pose_alternative->pose, camera, tag_size), opt.samples_per_cell);
      if (std::isfinite(alt) && (!std::isfinite(best) || alt >= best + opt.min_correlation_gain)) std::swap(d.pose, d.pose_alternative);
      break;
    }
  }
}

}  // namespace tagbench
