#pragma once
// The threshold-based quad-candidate stage (beyond the paper; AprilTag 2, Wang & Olson 2016) as one
// call, an alternative to gradient -> segmentation -> line_fit -> quad_search:
//   [halve (2x2 box average)] -> adaptive_threshold -> connected_components -> group_boundaries
//   -> fit_quads -> [corners back to full resolution] -> [refine_quad_edges on the full image]
// Output: quads in the Quad convention of quad_search.hpp (corners clockwise on screen, full-
// resolution pixels, pixel centres at integers; segments = -1, observed_perimeter = the quad's
// perimeter), ready for tag_homography + read_payload like the paper's quads.
#include <span>
#include <vector>

#include "boundaries.hpp"
#include "components.hpp"
#include "edge_refine.hpp"
#include "image.hpp"
#include "low_contrast_quads.hpp"
#include "quad_fit.hpp"
#include "quad_search.hpp"
#include "threshold.hpp"

namespace tagbench {

struct ThresholdQuadOptions {
  // Find candidates on a half-size image (2x2 block mean, blur.hpp's half_resolution): about 4x less
  // work in every stage below, at the price of tags under ~20 px (AprilTag 3: quad_decimate 2).
  bool halve = false;
  // Gaussian blur (blur.hpp) of the image the threshold sees, px of that image; 0 = off. Smooths
  // JPEG blocks and noise so thin rings stay connected; quads are still refined on the unblurred
  // image. (AprilTag 3: quad_sigma, default 0.)
  double blur_sigma = 0;
  // Beyond AprilTag 3: the blur chosen per image, for sharpened or noisy photographs. With enabled,
  // blur_sigma 0 and the full-resolution image, an image whose noise (estimate_noise_grey,
  // noise_estimate.hpp, on every 2nd column of 32 or more rows) is at least min_noise_grey grey levels is blurred by sigma px
  // before the threshold. Measured (realistic seed 1, 200 frames; session 33): the camera's
  // sharpening (`--sharpen 1,2`) cost the default profile 1100 -> 1042 tags (20-24 px 172 -> 146) and
  // took it to 1.11 x libapriltag d1's time; a fixed 0.8 px blur gets 1104 / 161 back on those frames
  // but loses 1100 -> 1043 on the unsharpened ones, whose noise is under 1.0 grey level in 95 % of
  // frames (sharpened: median 2). With it (variant `nblur=1`; session 33, the noise from every 2nd row): sharpened 1042 -> 1112 tags (20-24 px
  // 146 -> 163 of 188), 48.7 -> 40.3 ms a frame; unsharpened seed 1 1100 -> 1099 (20-24 px 172), seed
  // 2 1048 -> 1048; no wrong id; every ray-traced sweep (distance, angle, conditions) row for row the
  // same. On the corpus (1182 photographs) it gave 36h11 its first false detection (0 -> 1, a 0.27
  // sliver soft-decoded; SoftDecodeOptions::min_area_ratio removes it). Default on since session 34
  // (with the sliver guard; make bench: calibrated realistic sets and sweeps unchanged, sharpened seed
  // 1 1042 -> 1100 tags at 0.95 x libapriltag d1's time, corpus 16h5 0.223 -> 0.250 an image, 36h11
  // 0; the 6-DoF sweep's defocused small tags under Gaussian noise 731 -> 719 of 1000).
  struct NoiseBlur {
    bool enabled = true;
    double min_noise_grey = 1.42;  // > 0; 1.2 on the scale of the mean-based constant it was measured with
    double sigma = 0.8;           // px, > 0
  } noise_blur;
  ThresholdOptions threshold;
  // Dark regions 8-connected and light ones 4-connected (components.hpp) instead of the reverse
  // (AprilTag 3's pairing): a 10-12 px tag's black border is about one pixel wide, and when the tag
  // is rotated it is a diagonal staircase that 4-connectivity cuts into pieces, none of them a quad.
  // Default on (the default profile, issue 17): distance sweep 36h11 at 40 m (10 px) 39 -> 49 of 50,
  // at 45 m 17 -> 38 (libapriltag d1 38, 19); angle 80 degrees 35 -> 44 of 50 (d1 38); fewer 16h5
  // false detections on the corpus (0.098 -> 0.074 an image) and no slower.
  bool dark_eight_connected = true;
  BoundaryOptions boundaries;
  QuadFitOptions fit;      // fit.min_tag_width is in full-resolution pixels (halved internally, >= 3)
  bool refine_edges = true;  // refit the sides on the full-resolution image (edge_refine.hpp)
  EdgeRefineOptions refine;  // min_range_px is raised to 2 px when halving (one half-size pixel either side)
  // Beyond AprilTag 3, for speed: with enabled, a quad of a full-resolution pass (not halve: a
  // half-size fit is too rough for the check; realistic seed 2 lost 2 of 678 tags at half
  // resolution) whose border does not look like a tag's (border_contrast_plausible, payload_decode.hpp,
  // with this payload width and contrast floor) is left as fitted instead of refined: the decoder's
  // pre-filter (PayloadOptions::quick_reject) refuses it by the same test. Off here; on in the
  // default profile. The Detector sets payload_width to its families' largest and min_contrast to
  // PayloadOptions::min_contrast, and turns the check off without quick_reject.
  struct RefineCheck {
    bool enabled = false;
    int payload_width = 6;      // 1..8
    double min_contrast = 0.02;  // [0, 1]
  } refine_check;
  // A second threshold pass for faint small tags (low_contrast_quads.hpp); off here, the default
  // profile's value is in detector.hpp.
  LowContrastPassOptions low_contrast;
};

// Reusable buffers (only grow; nothing is allocated per frame once one image size has been seen,
// except the returned vector).
struct ThresholdQuadWorkspace {
  ImageF half, blurred, blur_tmp;
  BoundaryPassScratch pass;  // threshold, components, boundaries of the whole image
  std::vector<std::uint8_t> gave_quad;  // per group of pass.groups: 1 when its fit gave a quad (fit_quads)
  QuadFitScratch fit;
  EdgeRefineScratch refine;
  LowContrastScratch low_contrast;
};

struct ThresholdQuadStats {
  double ms_halve = 0, ms_blur = 0, ms_threshold = 0, ms_components = 0, ms_boundaries = 0, ms_fit = 0, ms_refine = 0;
  double ms_low_contrast = 0;  // the low-contrast pass (threshold to fit), included in ms_fit
  double noise_grey = -1;      // the image's noise estimate when noise_blur looked (else -1)
  double blur_sigma = 0;       // the blur the threshold saw, px (0: none)
  std::size_t components = 0, groups = 0, boundary_points = 0, quads = 0;
};

// The quad fit's options on the image the quads are found on: at half resolution (halved) the
// sizes in full-resolution pixels are halved (min_tag_width, at least 3; outer.max_size_px) and the
// outer-outline refit runs only with outer.at_half_resolution.
QuadFitOptions quad_fit_options_for(const QuadFitOptions& fit, bool halved);

// Whether find_threshold_quads works on the half-size image: opt.halve, and img at least 4 x 4.
bool threshold_quads_halved(const ImageF& img, const ThresholdQuadOptions& opt);

// Each of `quads` edge-refined on the full-resolution `img` with opt.refine (its min_range_px raised
// to 2 px when the quads came from the half-size image, threshold_quads_halved); a quad whose
// refinement fails keeps its corners. find_threshold_quads does this when opt.refine_edges.
void refine_threshold_quads(const ImageF& img, const ThresholdQuadOptions& opt, std::span<Quad> quads,
                            EdgeRefineScratch& scratch);

// Appends the candidate quads of `img` to `out` (cleared first).
void find_threshold_quads(const ImageF& img, const ThresholdQuadOptions& opt, ThresholdQuadWorkspace& ws,
                          std::vector<Quad>& out, ThresholdQuadStats* stats = nullptr);

}  // namespace tagbench
