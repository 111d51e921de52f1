#pragma once
// Beyond the paper: when NOT to apply the photometric refinement (photometric_refine.hpp). It fits
// one homography and a Gaussian blur reaching about one cell; two kinds of tag break that model and
// came out worse refined than with the edge-refined corners alone (raytrace conditions):
//   - a bent tag (two planes): the fit splits the difference between the halves and tilts the
//     corners (bent 10 degrees: orientation error median 0.67 deg refined vs 0.13 edge-refined);
//   - a heavily blurred edge (blur sigma 2 px on a 66 px tag: corner RMS 0.076 px vs 0.023).
// The guard measures the border (border_kink.hpp) on the unblurred image and leaves a detection's
// corners as they are when a side's kink or the edges' median blur exceeds its limit.
#include <span>

#include "border_kink.hpp"
#include "photometric_refine.hpp"

namespace tagbench {

struct PhotometricGuardOptions {
  bool enabled = true;         // default profile on (with the photometric refinement; paper(): off)
  // A side at least min_side_px long bent by more than max_kink_px (|SideKink::kink_px|) and by more than
  // min_kink_significance of its standard errors keeps the edge-refined corners. The measurement has a
  // systematic floor (bilinear sampling of a slanted edge): flat tags read up to 0.3 px and 16 standard
  // errors on the angle and distance sweeps, bent-10-degree tags 0.3-1.7 px; short sides read noise.
  double max_kink_px = 0.35;
  double min_kink_significance = 5;
  double min_side_px = 40;     // realistic set, 28-40 px tags: 24 cost 3 % of corner accuracy (JPEG and noise read as kinks)
  double max_blur_px = 1.5;    // an edge blur (median of the sides' SideKink::blur_px, px) above this likewise
  // The measurement; cells_across is set per family. The fold's crossing is taken at the side's middle
  // (max_fold_offset 0): searching for it fits noise on a straight side (a flat tag's kink read 0.21 px
  // median with the search, 0.07 without; 10-degree bends: 0.57 and 0.54).
  BorderKinkOptions kink = flat_kink_options();
  static BorderKinkOptions flat_kink_options() {
    BorderKinkOptions k;
    k.max_fold_offset = 0;
    return k;
  }
};

// refine_detections_photometric (photometric_refine.hpp) for the detections the guard passes; with
// guard.enabled false exactly refine_detections_photometric.
void refine_detections_photometric_guarded(std::span<Detection> detections, const ImageF& img,
                                           std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                           const PhotometricGuardOptions& guard);

// The guard's decision for one detection's corners (TL, TR, BR, BL), cells_across = d + 2.
bool photometric_model_fits(const ImageF& img, const Corners& corners, int cells_across,
                            const PhotometricGuardOptions& guard);

}  // namespace tagbench
