#pragma once
// Beyond the paper: straight edges found the way LSD finds them (R. Grompone von Gioi, J. Jakubowicz,
// J.-M. Morel, G. Randall, "LSD: a Line Segment Detector", IPOL 2012), written from the paper:
//   1. the image blurred (sigma), gradients by the 2x2 mask (at pixel corners, x + 0.5, y + 0.5);
//      pixels whose gradient is under `min_gradient` take no part;
//   2. pixels taken in decreasing gradient order as seeds; a region grows over 8-connected pixels
//      whose gradient direction is within `angle_tolerance_deg` of the region's mean direction (so an
//      edge's polarity is kept: dark-to-light and light-to-dark never join);
//   3. the region's rectangle: centroid and principal axis of its pixels (weighted by gradient),
//      length and width from their extent;
//   4. kept when its pixels fill at least `min_density` of the rectangle and it is meaningful in LSD's
//      a-contrario sense: NFA = (W H)^(5/2) 11 B(n, k, p) < 10^-log_eps, with n pixels in the
//      rectangle, k of them aligned (the region's) and p = tolerance / 180 degrees.
// It differs from the paper's gradient clustering (segmentation.hpp) in growing from the strongest
// pixels with a fixed angle tolerance instead of merging by the clusters' spread (K_D, K_M), which
// keeps the 8-25 px sides of small, blurred, noisy tags whole (the default profile's line quads,
// line_quads.hpp). Segments follow line_fit.hpp's convention: dark side on the left walking p0 -> p1.
// Coordinates: pixel centres at integer coordinates.
#include <cstdint>
#include <vector>

#include "image.hpp"
#include "line_fit.hpp"

namespace tagbench {

struct LineSegmentOptions {
  double sigma = 0.75;                // Gaussian blur before the gradient, px (LSD: 0.6 / its 0.8 scale)
  double angle_tolerance_deg = 22.5;  // LSD's tau, in (0, 90]
  // Gradient magnitude floor, grey levels (of 255) per pixel: LSD's q / sin(tau) with q = 2.
  double min_gradient = 3.0;  // > 0
  double min_density = 0.4;  // LSD: 0.7; 0.5 until session 23
  // Regions grow only from pixels at least this strong (grey levels per pixel), down to min_gradient:
  // weak texture then seeds no region of its own (most of the time went to such regions).
  double min_seed_gradient = 0;
  // -log10 of the accepted NFA (LSD: 0, one false segment an image; here up to 100: the quads made
  // of them must still read 2 bits closer than their family corrects or exactly, LineQuadOptions).
  double log_eps = -2.0;
  double min_length_px = 4.0;  // shorter segments are not reported
  // A region growing past this many pixels is dropped whole (its pixels stay used): the edges this is
  // for are a small tag's sides, and long edges and textures are where the time would go. 0: no cap.
  int max_region_pixels = 0;
  int max_cuts = 8;  // LSD's radius cuts of a region not dense enough, at most this many
  // A pixel takes part only when the pixels straight_check_px away along its edge (across its
  // gradient), on this many of its two sides (0: every pixel; 1: either; 2: both), point within the
  // tolerance of its own direction: blurred noise is aligned over a pixel or two, not along a line.
  int straight_sides = 0;  // 0..2
  double straight_check_px = 3;  // > 0
  bool straight_seeds_only = false;
  // Speed, exact: blocks of the image too flat for any gradient to reach min_gradient (the grey
  // range round them under min_gradient / sqrt 2, with room for rounding) are neither blurred nor
  // differentiated; their pixels take no part, as they would not anyway. The segments are the same
  // bit for bit either way (tests/test_line_segments.cpp); false computes every pixel.
  bool skip_flat_blocks = true;
};

// Buffers kept from one image to the next (storage only grows).
struct LineSegmentScratch {
  ImageF blurred, tmp;
  // The gradient grid with a one-entry rim on every side, so that a pixel's 8 neighbours are always
  // there to read: unit gradient per pixel corner, NaN where the pixel takes no part or is used.
  // With skip_flat_blocks, flat blocks out of every busy block's reach are not written (never read).
  struct Direction {
    float ux, uy;
  };
  std::vector<Direction> dir;
  std::vector<float> mag;
  std::vector<std::uint32_t> candidates, order, bin_count;
  std::vector<std::uint32_t> row_first;  // per gradient row, its first candidate (and one past the last)
  std::vector<std::uint16_t> bin;
  std::vector<std::uint8_t> aligned;
  struct RegionPixel {
    std::int32_t x, y;  // on the gradient grid
    std::uint32_t i;    // index into dir (rim included)
    float ux, uy;       // its direction (dir[i] is NaN while it is in the region)
  };
  std::vector<RegionPixel> region;
  std::vector<float> block_lo, block_hi;     // each block's grey range (skip_flat_blocks) ...
  std::vector<float> column_lo, column_hi;   // ... and a block row's, column by column
  std::vector<std::uint8_t> busy, need, part;  // blocks differentiated; blurred; what each gets
  std::vector<Direction> flat_row;           // a row of NaN directions, copied into flat blocks
};

// Throws std::invalid_argument when min_gradient <= 0, angle_tolerance_deg is not in (0, 90],
// straight_sides is not in 0..2 or straight_check_px <= 0.
std::vector<Segment> detect_line_segments(const ImageF& img, const LineSegmentOptions& opt, LineSegmentScratch& scratch);

}  // namespace tagbench
