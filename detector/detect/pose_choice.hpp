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
// Under a lens distortion (OpenCV's k1, k2, p1, p2, k3) the pattern is projected through the pose and
// the lens (with_lens); a homography of the corners cannot map a distorted tag.
#include <array>
#include <optional>
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
  // The rule above holds for tags the reported pose sees at least this steeply (degrees between the
  // tag's normal and the line of sight); gentler views follow the gentle_* rule below, as with the
  // above a tag that is not one plane (bent 30 degrees, seen at 0-30 degrees) matches neither
  // solution's pattern well and the correlation would pick the worse one (conditions bent 30:
  // orientation p90 7.0 -> 51 deg with this rule at every view).
  double min_view_angle_deg = 70;
  // Beyond session 7: judge under a lens distortion too, projecting the pattern through the pose and
  // the lens (pattern_correlation_through_lens). Off: the stage is skipped when a distortion is given
  // (as before). Default profile on; paper(): the whole stage is off.
  bool with_lens = true;
  // Beyond session 7, views gentler than min_view_angle_deg. There the corners decide unless the
  // alternative fits them within this RMS (px) too, i.e. within the corners' own noise: a small tag
  // (10-20 px) at 10-60 degrees, whose two solutions fit the corners within 0.05-0.45 px, the wrong
  // one as often as not (6-DoF sweep: 44 of the 76 poses > 10 degrees off had the right alternative).
  // A tag that is not one plane (conditions bent 30-40 degrees) has an alternative fitting its
  // corners 1-3 px worse, which this leaves alone. 0: gentle views are not judged (session 7).
  // Measured (6-DoF sweep, 695 detected): > 10 degrees off 76 -> 34 (39 fixed, 4 broken), p90 11.2 -> 5.3.
  double gentle_max_alternative_rms_px = 0.6;
  double gentle_min_correlation_gain = 0;  // as min_correlation_gain, at gentle views
  int gentle_samples_per_cell = 5;         // as samples_per_cell, at gentle views
  // At gentle views the pattern is blurred by a Gaussian of this sigma (px) before it is correlated
  // (pattern_correlation_through_lens): the two solutions' patterns differ by a fraction of a pixel at
  // the cells' edges, which a sharp pattern misjudges on a defocused image. 0: sharp.
  double gentle_model_blur_px = 1;
  // Tell the user when the image cannot decide: a detection whose alternative was judged (its rule's
  // RMS bound met) and whose two pattern correlations differ by less than this is marked
  // Detection::pose_ambiguous; both solutions stay reported with their pattern_correlation. 0: never.
  // 6-DoF sweep: 133 of 695 detections marked, holding 32 of the 34 poses > 10 degrees off.
  double ambiguous_correlation_gap = 0.001;
};

// Pearson correlation between the printed pattern `cells` (1 = white, every cell of the n x n layout)
// and the image sampled (bilinear) at the pattern's points mapped through `corners`' homography (the
// black square's corners, TL, TR, BR, BL); NaN when fewer than half the points are inside the image.
double pattern_correlation(const ImageF& img, const TagCells& cells, const Corners& corners, int samples_per_cell);

// The tag point (u1, u2) of the black square [-1,1]^2 (printed axes) projected through `pose`, the
// pinhole `camera` and, when given, the lens distortion (OpenCV's model: k1, k2, p1, p2, k3 applied to
// the normalised coordinates); pixels. Non-finite when the point is not in front of the camera.
Eigen::Vector2d project_tag_point(const Pose& pose, const CameraIntrinsics& camera, double tag_size,
                                  const std::optional<std::array<double, 5>>& distortion, double u1, double u2);

// As pattern_correlation, the pattern's points mapped by project_tag_point (through the lens, when given);
// blur_px > 0: the pattern blurred by a Gaussian of that sigma (pixels, converted to tag units by the
// black square's mean projected side) before it is correlated, as a defocused image shows it.
double pattern_correlation_through_lens(const ImageF& img, const TagCells& cells, const Pose& pose,
                                        const CameraIntrinsics& camera, double tag_size,
                                        const std::optional<std::array<double, 5>>& distortion, int samples_per_cell,
                                        double blur_px = 0);

// For every detection with both `pose` and `pose_alternative` (and a family among `families`): the
// two swapped when the rule above prefers the alternative; both solutions' pattern_correlation set
// when judged, and pose_ambiguous as ambiguous_correlation_gap says. With a `distortion`, only when
// opt.with_lens (the pattern then goes through the lens).
void choose_poses_photometric(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                              const CameraIntrinsics& camera, double tag_size, const PoseChoiceOptions& opt,
                              const std::optional<std::array<double, 5>>& distortion = std::nullopt);

}  // namespace tagbench
