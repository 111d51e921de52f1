#include "detect/photometric_guard.hpp"

#include <cmath>

#include "detect/detector.hpp"

namespace tagbench {

bool photometric_model_fits(const ImageF& img, const Corners& corners, int cells_across,
                            const PhotometricGuardOptions& guard) {
  BorderKinkOptions measure = guard.kink;
  measure.cells_across = cells_across;
  const auto sides = measure_border_kinks(img, corners, measure);
  if (!sides) return false;
  for (std::size_t i = 0; i < 4; ++i) {
    const SideKink& s = (*sides)[i];
    if (!s.valid || (corners[(i + 1) % 4] - corners[i]).norm() < guard.min_side_px) continue;
    const double k = std::abs(s.kink_px);
    if (k > guard.max_kink_px && k > guard.min_kink_significance * s.kink_se_px) return false;
  }
  return median_blur_px(*sides) <= guard.max_blur_px;
}

void refine_detections_photometric_guarded(std::span<Detection> detections, const ImageF& img,
                                           std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                           const PhotometricGuardOptions& guard) {
  for (Detection& d : detections)
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      if (guard.enabled && !photometric_model_fits(img, d.corners, f.payload_width() + 2, guard)) break;
      refine_detections_photometric(std::span<Detection>(&d, 1), img, std::span<const TagFamily>(&f, 1), opt);
      break;
    }
}

}  // namespace tagbench
