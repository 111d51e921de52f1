#pragma once
// Beyond the paper: photometric refinement of a decoded tag's homography against its known printed
// pattern. Once a quad is decoded its every cell is known (black ring, payload bits, white ring), so
// every black/white transition inside the tag -- not only the four outer sides -- says where the tag
// is. The refinement fits the image over the pixels near those transitions with a rendered model
//   I(x) = A(u) + B(u) T_sigma(u),   u = G(x)  (image -> tag square [-1,1]^2, a homography)
// where T_sigma is the printed pattern (0 black, 1 white) blurred by a Gaussian of sigma pixels (in the
// image: per pixel converted to tag units through G's local Jacobian, separately along each tag axis,
// which is exact for a cell edge under a locally affine view), and A, B are affine in the image
// coordinates x (black level, contrast, and their shading across the tag: a level off by 1 % of the
// contrast at an edge would move it by about 0.025 sigma, so a constant level is not enough).
// Gauss-Newton over G's 8 parameters, sigma and the 6 photometric ones, with Huber weights (an
// occluder or a specular spot is down-weighted, not fitted). The refined corners are G^-1 of the black square's corners.
//
// Units: pixels (centres at integer coordinates), intensities as in image.hpp ([0, 1]); tag
// coordinates: the black square is [-1,1]^2 in printed axes (x right, y down), a cell 2/(d+2) wide.
// The pattern is the printed layout of tag_layout.hpp (white ring, black ring, payload; 1 = white);
// outside the white ring the model assumes white (the ring's outer half is not used).
//
// Safeguards: nullopt (the caller keeps its corners) when the tag is too small, too few pixels are
// usable, the contrast comes out below min_contrast, the blur above max_blur_cells, or a corner would
// move by more than max_corner_shift_px. A homography cannot fit a tag seen through lens distortion:
// the detector skips this stage when DetectorOptions::distortion is given.
#include <memory>
#include <optional>
#include <span>

#include "../codes/tag_family.hpp"
#include "../codes/tag_layout.hpp"
#include "homography.hpp"
#include "image.hpp"

namespace tagbench {

struct Detection;  // detector.hpp

struct PhotometricRefineOptions {
  bool enabled = true;               // default profile on; DetectorOptions::paper(): off (the quad stage's corners)
  int iterations = 2;                // Gauss-Newton steps (one pass over the pixels each)
  double margin_cells = 0.5;         // how far past the black square the fit reaches, in cells (< 1: inside the white ring)
  double band_px = 1.5;              // pixels farther than this from every transition of the pattern are left out
  double initial_blur_px = 0.6;      // sigma's starting value, px
  int max_pixels = 2500;             // more usable pixels than the budget are subsampled evenly (the cost is
                                     // about 250 instructions a pixel and pass, vectorised: photometric_model.hpp;
                                     // precision ~ 1/sqrt(pixels))
  double pixels_per_side_px = 25;    // a larger tag's budget: this many pixels per pixel of its mean side, if above max_pixels
  int min_pixels = 40;               // fewer: no refinement
  double min_black_square_px = 6;    // smaller tags (mean side, px) are left alone
  // A larger move rejects the refinement (then the tag is not what the model says: bent, or the quad
  // stage's corners were far off). 0.5 until session 32: with the model on linear intensities
  // (`gamma`), 1 px and max_blur_cells 0.5 halved the realistic set's corner error (median 0.154 ->
  // 0.103 px, 90th percentile 0.649 -> 0.471; docs/default-profile.md).
  double max_corner_shift_px = 1.0;
  double max_blur_cells = 0.5;       // a fitted sigma above this fraction of a cell rejects it: the model
                                     // reaches one cell either way, so heavier blur biases it (0.35 until
                                     // session 32)
  double huber = 0.15;               // Huber threshold, fraction of the tag's contrast (white - black)
  double min_contrast = 0.02;        // white minus black at the tag centre (intensity units) at least this
  // The pixels' intensities are raised to this power before the fit: the input's encoding gamma
  // (DetectorOptions::input_gamma, which the detector sets it from), so that the model, a blurred
  // pattern mixed linearly, meets linear intensities. 1: the image as it is; not finite and > 0: no
  // refinement.
  double gamma = 1.0;
  // Speed: J^T W J summed as column dot products instead of Eigen's general rank update (about a
  // third of its instructions at 15 columns; photometric_model.hpp); false keeps the rank update.
  // The same sums rounded in another order (1e-7 relative): corners move by ~1e-6 px.
  bool column_dot_sums = true;
};

// A part of the tag the fit leaves out (a known occluder's, photometric_guard.hpp): tag coordinates
// (the black square [-1,1]^2) u1 in [u1_lo, u1_hi] and u2 in [u2_lo, u2_hi].
struct TagBox {
  double u1_lo = 0, u1_hi = 0, u2_lo = 0, u2_hi = 0;
};

// Buffers of the refinement kept from one tag to the next (their storage only grows): the pixel
// selection's rows, the pixels and samples, the model's per-pixel arrays and Jacobian (about 40
// arrays of up to max_pixels floats). Fresh ones for every tag cost about a third of the
// refinement's time (allocation and the first touch of new pages), so a detector keeps one in its
// workspace (DetectorWorkspace). One workspace must not be used by two calls at once.
struct PhotometricWorkspace {
  PhotometricWorkspace();
  ~PhotometricWorkspace();
  PhotometricWorkspace(PhotometricWorkspace&&) noexcept;
  PhotometricWorkspace& operator=(PhotometricWorkspace&&) noexcept;
  struct Impl;  // photometric_refine.cpp
  std::unique_ptr<Impl> impl;
};

// The black square's corners (TL, TR, BR, BL of the printed tag, as in Detection) refined on `img`
// (the unblurred image) for the tag whose printed cells are `cells`; nullopt when rejected (above).
// Pixels whose tag coordinates (through the starting corners) fall in an `excluded` box are not used.
// `workspace`: caller-owned buffers (identical results); nullptr: buffers of this call only.
std::optional<Corners> refine_corners_photometric(const ImageF& img, const TagCells& cells, const Corners& corners,
                                                  const PhotometricRefineOptions& opt,
                                                  std::span<const TagBox> excluded = {},
                                                  PhotometricWorkspace* workspace = nullptr);

// Moves a detection onto new corners, its homography and centre with them; false (and the detection
// unchanged) when `corners` is empty or gives no homography.
bool move_detection_to(Detection& d, const std::optional<Corners>& corners);

// Every detection whose family is among `families`: corners, homography and centre replaced by the
// refined ones where the refinement succeeds; the rest left alone. `workspace` as above.
void refine_detections_photometric(std::span<Detection> detections, const ImageF& img,
                                   std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                   PhotometricWorkspace* workspace = nullptr);

}  // namespace tagbench
