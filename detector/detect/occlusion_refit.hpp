#pragma once
// Beyond the paper: after decoding, each side of a detection is checked against what the decoded tag
// must look like there, and a partly hidden side is re-fitted from its visible part only (issue 17:
// an occluded edge must not pull its side, a wrong pose is worse than none).
//
// Along every side, samples about `sample_spacing_px` apart (leaving `end_margin_px` at each corner)
// read the image half a cell inside (the black ring) and half a cell outside (the white ring). A
// sample AGREES with the tag when its contrast (out - in) / (out + in) is at least `agree_fraction`
// of the median contrast over all four sides (a ratio, so lighting gradients and blur do not
// matter). A side whose samples all agree (up to `max_disagree`) is kept as it is. Otherwise the
// disagreeing samples, widened by `erode_samples` on each side (the occluder's blurred edge), are
// dropped; at each remaining sample the dark-to-light step is located along the normal (edge_refine's
// locator: the mean offset weighted by the squared positive derivative) and the side's line is the
// total-least-squares fit to those edge points, `iterations` times. Corners are the intersections of
// consecutive sides' lines, so a side seen over 20 % of its length still fixes its line.
//
// A tag whose cells are under `min_cell_px` across any side (small, or steeply slanted) is left as it
// is: its rings are too thin to tell an occluder from blur. Otherwise the detection is withdrawn (nullopt) when a side has less than `min_visible` of its samples
// agreeing or when a
// corner would move by more than `max_corner_shift_cells` cells (the sides disagree). A median
// contrast under `min_median_contrast` is too faint to judge: the detection is kept as it is.
//
// Units: pixels; corners in the Detection convention (printed order TL, TR, BR, BL, any winding).
#include <array>
#include <optional>

#include "homography.hpp"
#include "image.hpp"

namespace tagbench {

struct OcclusionRefitOptions {
  double sample_spacing_px = 1.0;
  double end_margin_px = 1.5;
  double agree_fraction = 0.5;
  double max_disagree = 0.05;       // a side with at most this fraction disagreeing is left alone
  int erode_samples = 1;
  double min_visible = 0.08;        // of a side's samples, agreeing after the erosion
  double min_median_contrast = 0.2;
  double max_corner_shift_cells = 0.5;
  int iterations = 2;
  // Cells narrower than this (px, across any side) are too thin to judge: the detection is kept.
  double min_cell_px = 2.5;
  // The step's locator raises each pixel to this power before interpolating (the input's encoding
  // gamma, DetectorOptions::input_gamma; linear_corners.hpp): a re-fitted side is then placed as the
  // decoded tags' other sides are. The agreement test reads the image as it is. The detector sets it
  // from DetectorOptions::input_gamma. Not finite and > 0: the detection is kept as it is.
  double gamma = 1.0;
};

// What refit_occluded_sides did (for tests and traces).
struct OcclusionRefitResult {
  std::optional<Corners> corners;  // nullopt: withdraw the detection
  int sides_refitted = 0;
  // Per re-fitted side i (corners[i] -> corners[i + 1]): the part its fit left out, as fractions of
  // the side's length from corners[i] (first and last dropped sample; the occluder's extent along it).
  std::array<std::optional<std::array<double, 2>>, 4> hidden{};
};

// `img`: the unblurred image; `cells_across`: cells across the black square (payload width + 2).
OcclusionRefitResult refit_occluded_sides(const ImageF& img, const Corners& corners, int cells_across,
                                          const OcclusionRefitOptions& opt = {});

}  // namespace tagbench
