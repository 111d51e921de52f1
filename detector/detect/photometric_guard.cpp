#include "detect/photometric_guard.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "detect/detector.hpp"

namespace tagbench {

namespace {

enum class ModelFit { kFits, kBent, kBlurred, kVeryBlurred };

ModelFit judge(const ImageF& img, const Corners& corners, int cells_across, const PhotometricGuardOptions& guard,
               const HiddenSides& hidden) {
  BorderKinkOptions measure = guard.kink;
  measure.cells_across = cells_across;
  const auto sides = measure_border_kinks(img, corners, measure);
  if (!sides) return ModelFit::kBent;
  for (std::size_t i = 0; i < 4; ++i) {
    const SideKink& s = (*sides)[i];
    if (!s.valid || (corners[(i + 1) % 4] - corners[i]).norm() < guard.min_side_px) continue;
    if (guard.skip_hidden_sides && hidden[i]) continue;
    const double k = std::abs(s.kink_px);
    if (k > guard.max_kink_px && k > guard.min_kink_significance * s.kink_se_px) return ModelFit::kBent;
  }
  const double blur = median_blur_px(*sides);
  return blur <= guard.max_blur_px ? ModelFit::kFits
         : blur <= guard.keep_scale_min_blur_px ? ModelFit::kBlurred
                                                 : ModelFit::kVeryBlurred;
}

const std::array<Eigen::Vector2d, 4> kTagCorners{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                                 Eigen::Vector2d(-1, 1)};

}  // namespace

bool photometric_model_fits(const ImageF& img, const Corners& corners, int cells_across,
                            const PhotometricGuardOptions& guard, const HiddenSides& hidden) {
  return judge(img, corners, cells_across, guard, hidden) == ModelFit::kFits;
}

std::optional<Corners> align_tag_scale(const Corners& refined, const Corners& edge) {
  const auto H = tag_homography(refined);
  if (!H || !tag_homography(edge)) return std::nullopt;
  // Corner i = H(s u_i + d); Gauss-Newton on (s, d) from (1, 0), the Jacobian of H at each point.
  double sc = 1;
  Eigen::Vector2d d = Eigen::Vector2d::Zero();
  for (int it = 0; it < 3; ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 4; ++i) {
      const Eigen::Vector2d u = sc * kTagCorners[i] + d;
      const Eigen::Vector3d h = *H * Eigen::Vector3d(u.x(), u.y(), 1);
      const Eigen::Vector2d p = h.head<2>() / h.z();
      Eigen::Matrix2d Ju;  // d p / d u
      for (int k = 0; k < 2; ++k) Ju.col(k) = ((*H)(Eigen::seq(0, 1), k) - p * (*H)(2, k)) / h.z();
      Eigen::Matrix<double, 2, 3> J;
      J.col(0) = Ju * kTagCorners[i];
      J.rightCols<2>() = Ju;
      A += J.transpose() * J;
      b += J.transpose() * (edge[i] - p);
    }
    const Eigen::Vector3d step = A.ldlt().solve(b);
    if (!step.allFinite()) return std::nullopt;
    sc += step(0), d += step.tail<2>();
  }
  Corners out;
  for (std::size_t i = 0; i < 4; ++i) out[i] = apply_homography(*H, sc * kTagCorners[i] + d);
  return out;
}

std::vector<TagBox> hidden_tag_boxes(const Corners& corners, int cells_across, const HiddenSides& hidden,
                                     const PhotometricGuardOptions& guard) {
  std::vector<TagBox> boxes;
  if (!(guard.hidden_depth_cells > 0) || cells_across < 1) return boxes;
  const auto H = tag_homography(corners);
  if (!H) return boxes;
  const Eigen::Matrix3d Hinv = H->inverse();
  const double cell = 2.0 / cells_across, pad = guard.hidden_pad_cells * cell, depth = guard.hidden_depth_cells * cell;
  constexpr double kOut = 4;  // past any reach of the refinement (tag units)
  for (std::size_t i = 0; i < 4; ++i) {
    if (!hidden[i]) continue;
    const Eigen::Vector2d a = corners[i], e = corners[(i + 1) & 3];
    const Eigen::Vector2d p = apply_homography(Hinv, a + (*hidden[i])[0] * (e - a));
    const Eigen::Vector2d q = apply_homography(Hinv, a + (*hidden[i])[1] * (e - a));
    // The side is u2 = +-1 (top, bottom) when its ends differ in u1, else u1 = +-1.
    const Eigen::Vector2d ta = apply_homography(Hinv, a), te = apply_homography(Hinv, e);
    const bool along_u1 = std::abs(te.x() - ta.x()) > std::abs(te.y() - ta.y());
    const double lo = along_u1 ? std::min(p.x(), q.x()) - pad : std::min(p.y(), q.y()) - pad;
    const double hi = along_u1 ? std::max(p.x(), q.x()) + pad : std::max(p.y(), q.y()) + pad;
    const double edge = along_u1 ? (ta.y() + te.y() > 0 ? 1.0 : -1.0) : (ta.x() + te.x() > 0 ? 1.0 : -1.0);
    const double in = edge - edge * depth, out = edge * kOut;
    TagBox b;
    if (along_u1)
      b = {lo, hi, std::min(in, out), std::max(in, out)};
    else
      b = {std::min(in, out), std::max(in, out), lo, hi};
    boxes.push_back(b);
  }
  return boxes;
}

void refine_detections_photometric_guarded(std::span<Detection> detections, const ImageF& img,
                                           std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                           const PhotometricGuardOptions& guard, std::span<const HiddenSides> hidden,
                                           PhotometricWorkspace* workspace) {
  for (std::size_t k = 0; k < detections.size(); ++k) {
    Detection& d = detections[k];
    const HiddenSides h = k < hidden.size() ? hidden[k] : HiddenSides{};
    const bool occluded = h[0] || h[1] || h[2] || h[3];
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      const ModelFit fit = guard.enabled ? judge(img, d.corners, f.payload_width() + 2, guard, h) : ModelFit::kFits;
      if (fit == ModelFit::kBent || fit == ModelFit::kBlurred || (fit == ModelFit::kVeryBlurred && !guard.blurred_keep_scale))
        break;
      // Plain refinement, or (an occluded side's hidden stretch, or heavy blur) the refinement without
      // the hidden stretch, its result scaled onto the edge corners when heavily blurred.
      if (!guard.enabled || (!occluded && fit != ModelFit::kVeryBlurred)) {
        refine_detections_photometric(std::span<Detection>(&d, 1), img, std::span<const TagFamily>(&f, 1), opt, workspace);
        break;
      }
      const std::vector<TagBox> boxes = hidden_tag_boxes(d.corners, f.payload_width() + 2, h, guard);
      const auto c = refine_corners_photometric(img, tag_cells(f, d.id), d.corners, opt, boxes, workspace);
      move_detection_to(d, fit == ModelFit::kVeryBlurred && c ? align_tag_scale(*c, d.corners) : c);
      break;
    }
  }
}

}  // namespace tagbench
