#pragma once
// Beyond the paper: how far each side of a decoded or candidate quad is from a straight line, and
// how blurred its edge is, measured on the UNBLURRED image. A tag folded along a centre line (a bent
// sticker, a tag on a curved box lid) is two planes: two opposite sides are each two straight pieces
// meeting at a kink where the fold line crosses them, the other two stay straight; no homography maps
// the whole tag. Two units use this measurement: the second-chance read of a folded tag
// (bent_decode.hpp) and the guard that keeps the photometric refinement, which fits one homography,
// off bent or heavily blurred tags (photometric_guard.hpp).
//
// Method: the flat homography H of the quad (tag square [-1,1]^2 -> image) gives `samples` points
// along each side, at tag parameter s in [-1 + end_margin, 1 - end_margin] (tag units along the side).
// At each the profile is scanned along the side's outward normal (dark inside, light outside, as in
// edge_refine.hpp) over +-range px; the edge's offset o is the mean of the scan offsets weighted by the
// squared positive derivative, the scan re-centred on it once. The offsets are then fitted (least
// squares) by a broken line o(s) = a + b s + c |s - s0| for s0 on a grid in [-max_fold_offset,
// max_fold_offset]; the best s0 is where the fold crosses the side and c (px) is the kink: the change
// of slope, in px per tag unit, halved. A straight side gives c near 0. The edge's blur is the
// weighted spread of the squared derivative: for a Gaussian step of sigma px the squared derivative is a
// Gaussian of sigma / sqrt(2) (the central difference's own width taken off).
//
// Units: pixels (centres at integer coordinates), intensities in [0, 1] (image.hpp).
#include <array>
#include <optional>
#include <span>

#include <Eigen/Core>

#include "homography.hpp"
#include "image.hpp"

namespace tagbench {

struct BorderKinkOptions {
  int samples = 16;               // scan points per side
  double end_margin = 0.15;       // tag units left out at each end of a side (of 2), away from the corners
  double range_cells = 0.6;       // scan reach either side of the straight side, in cells (the black ring is one
                                  // cell: more would reach the payload's edges) ...
  double min_range_px = 1.5;      // ... at least this
  double step_px = 0.25;          // scan step along the normal
  double derivative_half_px = 0.5;  // central difference I(s + h) - I(s - h)
  double max_fold_offset = 0.5;   // the fold's crossing searched within this of the side's middle (tag units)
  int cells_across = 8;           // cells across the black square (d + 2)
};

struct SideKink {
  bool valid = false;       // enough edge points were found (at least half of `samples`)
  double kink_px = 0;       // c above: 0 for a straight side; its sign says which way the side bends
  double fold_s = 0;        // s0: where the two pieces meet, tag units along the side from its middle
  double rms_px = 0;        // the broken line's residual
  double kink_se_px = 0;    // kink_px's standard error from that residual (edge noise, not the fold)
  Eigen::Vector2d fold_point = Eigen::Vector2d::Zero();  // the edge at s0 in the image
  std::array<Eigen::Vector2d, 2> ends{};                 // the broken line's ends (s = -1, +1) in the image
  double blur_px = 0;       // median edge sigma over the side's scans
};

// Side i runs from corners[i] to corners[i + 1] (any consistent winding); nullopt when the corners
// give no homography or cells_across < 1. `corners` as in Corners (homography.hpp).
std::optional<std::array<SideKink, 4>> measure_border_kinks(const ImageF& img, const Corners& corners,
                                                            const BorderKinkOptions& opt = {});

// The broken line o(s) = a + b s + c |s - s0| fitted to points (s, o) by least squares, the fold s0 on
// a grid of 0.025 in [-max_s0, max_s0] (the one of least residual); ssr its residual sum of squares,
// c_var c's variance per unit residual variance ((A^T A)^-1_cc). nullopt when no s0 gives a finite fit.
struct BrokenLine {
  double a = 0, b = 0, c = 0, s0 = 0, ssr = 0, c_var = 0;
};
std::optional<BrokenLine> fit_broken_line(std::span<const Eigen::Vector2d> pts, double max_s0);

// The largest |kink_px| of the valid sides (0 when none is valid), and the median blur of the valid sides.
double max_kink_px(const std::array<SideKink, 4>& sides);
// The largest |kink_px| / kink_se_px of the valid sides (how many standard errors the most bent side is from straight).
double max_kink_significance(const std::array<SideKink, 4>& sides);
double median_blur_px(const std::array<SideKink, 4>& sides);

}  // namespace tagbench
