#pragma once
// Beyond the paper: which of the planar pose ambiguity's two solutions (estimate_poses.hpp,
// tag_pose_solutions) to report, judged on the image. The corners' reprojection error decides
// between them otherwise; at grazing views (a 66 px tag at 85 degrees is a sliver about 6 px
// thick, its short sides meeting the long ones at under 20 degrees) a few pixels' error along the
// sliver reverses the perspective cue, and the flipped solution fits the corners better (angle sweep
// 85 degrees: 170 degrees orientation error, corner RMS 5.5 px). The decoded tag's printed pattern
// tells them apart: each solution's projection of the pattern (white ring, black ring, payload) is
// compared with the image, and the alternative is reported when it correlates better.
//
// Units: pixels (centres at integer coordinates), intensities as in image.hpp; tag size in metres.
// Pinhole only: the detector skips the stage when a lens distortion is given.
#include <span>

#include "../codes/tag_family.hpp"
#include "../codes/tag_layout.hpp"
#include "homography.hpp"
#include "image.hpp"
#include "pose.hpp"

namespace tagbench {

struct Detection;  // detector.hpp

struct PoseChoiceOptions {
  bool enabled = true;                 // default profile on (with DetectorOptions::refine_pose); paper(): off
  // The alternative is considered only when its corners' reprojection RMS is at most this (px): a
  // far worse fit is no ambiguity (the near face-on case is left to the corners alone).
  double max_alternative_rms_px = 6;
  // ... and reported when its pattern correlation exceeds the best solution's by at least this.
  double min_correlation_gain = 0.02;
  int samples_per_cell = 3;            // per cell and axis, at the sub-cells' centres
  // Only tags the reported pose sees at least this steeply (degrees between the tag's normal and the
  // line of sight) are judged: at gentler views the corners decide reliably, and a tag that is not one
  // plane (bent 30 degrees, seen at 0-30 degrees) matches neither solution's pattern well, so the
  // correlation would pick the worse one (conditions bent 30: orientation p90 7.0 -> 51 deg without this).
  double min_view_angle_deg = 70;
};

// Pearson correlation between the printed pattern `cells` (1 = white, every cell of the n x n layout)
// and the image sampled (bilinear) at the pattern's points mapped through `corners`' homography (the
// black square's corners, TL, TR, BR, BL); NaN when fewer than half the points are inside the image.
double pattern_correlation(const ImageF& img, const TagCells& cells, const Corners& corners, int samples_per_cell);

// For every detection with both `pose` and `pose_alternative` (and a family among `families`): the
// two swapped when the rule above prefers the alternative.
void choose_poses_photometric(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                              const CameraIntrinsics& camera, double tag_size, const PoseChoiceOptions& opt);

}  // namespace tagbench
