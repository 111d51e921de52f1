#pragma once
// Beyond the paper: when NOT to apply the photometric refinement (photometric_refine.hpp). It fits
// one homography and a Gaussian blur reaching about one cell; two kinds of tag break that model and
// came out worse refined than with the edge-refined corners alone (raytrace conditions):
//   - a bent tag (two planes): the fit splits the difference between the halves and tilts the
//     corners (bent 10 degrees: orientation error median 0.67 deg refined vs 0.13 edge-refined);
//   - a heavily blurred edge (blur sigma 2 px on a 66 px tag: corner RMS 0.076 px vs 0.023).
// The guard measures the border (border_kink.hpp) on the unblurred image and leaves a detection's
// corners as they are when a side's kink or the edges' median blur exceeds its limit. Two cases are
// judged differently (options below): an occluded tag (sides occlusion_refit.hpp re-fitted) is refined
// without its hidden part, and a very blurred one is refined and then scaled onto its edge corners.
#include <array>
#include <optional>
#include <span>
#include <vector>

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
  // Occluded tags (a side re-fitted from its visible part by occlusion_refit.hpp, HiddenSides below):
  // the border kink reads the occluder's edge where it crosses such a side, not a bent tag, so
  // with skip_hidden_sides the kink test leaves those sides out (the others are still judged; before
  // this, occlusion 40 % edge: the guard refused every tag, orientation p90 0.30 deg, max 2.1) ...
  bool skip_hidden_sides = true;
  // ... and the refinement leaves out the hidden part (TagBox, photometric_refine.hpp): along the side
  // the occluder's extent widened by hidden_pad_cells each way, across it from outside the reach to
  // hidden_depth_cells inside the black square (the ring the refit's samples judged; 0: no mask; without
  // it the Huber-weighted occluder pulls the fit: occlusion 60 % corner RMS median 0.031 px vs 0.019 unrefined).
  double hidden_depth_cells = 1.0;
  double hidden_pad_cells = 0.5;
  // A tag refused for its blur alone (straight sides, median blur above max_blur_px) is refined all
  // the same, and the refined homography then moved by a similarity of the tag plane (scale and shift,
  // least squares) onto the edge-refined corners: the model's bias under heavy blur is mostly a scale
  // of the tag square, which changes the pose's distance but not its rotation, so the corners keep the
  // edge-refined accuracy and the orientation the pattern's (blur 3 px: orientation median 0.75 deg
  // refused, 0.50 refined; corner RMS 0.17 and 0.27 px). false: such a tag keeps its edge-refined corners.
  bool blurred_keep_scale = true;
  // ... only when the median blur is above this (px); between max_blur_px and this the edge-refined
  // corners are kept (blur 2 px: corner RMS 0.023 edge-refined, 0.033 aligned; orientation median 0.09 /
  // 0.14 deg). 2: blur 3 px corner RMS median 0.172 -> 0.155 px, orientation 0.745 -> 0.618 deg (2.5: 0.171, 0.723).
  double keep_scale_min_blur_px = 2.0;
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

// Per side i (corners[i] -> corners[i + 1]) the part an occluder hides, as fractions of the side from
// corners[i] (OcclusionRefitResult::hidden); nullopt: the side is seen whole.
using HiddenSides = std::array<std::optional<std::array<double, 2>>, 4>;

// refine_detections_photometric (photometric_refine.hpp) for the detections the guard passes; with
// guard.enabled false exactly refine_detections_photometric. `hidden`: empty, or one entry per detection.
// `workspace`: the refinement's buffers (nullptr: its own, allocated per call).
void refine_detections_photometric_guarded(std::span<Detection> detections, const ImageF& img,
                                           std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                           const PhotometricGuardOptions& guard,
                                           std::span<const HiddenSides> hidden = {},
                                           PhotometricWorkspace* workspace = nullptr);

// The guard's decision for one detection's corners (TL, TR, BR, BL), cells_across = d + 2.
bool photometric_model_fits(const ImageF& img, const Corners& corners, int cells_across,
                            const PhotometricGuardOptions& guard, const HiddenSides& hidden = {});

// `refined` (the photometric refinement's corners) moved by the similarity of the tag plane (uniform
// scale about the tag centre, then a shift; tag units) that brings them nearest, least squares, to
// `edge` (the same tag's edge-refined corners); nullopt when either gives no homography.
std::optional<Corners> align_tag_scale(const Corners& refined, const Corners& edge);

// The tag-coordinate boxes the refinement leaves out for `hidden` (empty when hidden_depth_cells is 0).
std::vector<TagBox> hidden_tag_boxes(const Corners& corners, int cells_across, const HiddenSides& hidden,
                                     const PhotometricGuardOptions& guard);

}  // namespace tagbench
