#pragma once
// Local adaptive threshold (beyond the paper; AprilTag 2, Wang & Olson 2016, section III-A): every
// pixel is classed dark, light or unknown against the midpoint of the minimum and maximum intensity
// of its neighbourhood. The neighbourhood is tile based for speed: the image is cut into
// tile_size x tile_size tiles, each tile's min and max are taken, and a pixel uses the min and max
// over its own tile and the 8 around it (so neighbouring pixels share most of their window and the
// threshold has no seams at tile borders). Where max - min < min_contrast nothing can be an edge:
// the pixel is unknown and later stages skip it (flat regions cost nothing after this stage).
//
// Conventions (image.hpp): float intensities in [0, 1], x right, y down, row-major. The last tile of
// a row or column may be partial (the image need not be a multiple of tile_size).
#include <cstdint>
#include <vector>

#include "image.hpp"

namespace tagbench {

inline constexpr std::uint8_t kTernaryDark = 0;
inline constexpr std::uint8_t kTernaryLight = 255;    // kTernaryDark + kTernaryLight == 255: "opposite classes"
inline constexpr std::uint8_t kTernaryUnknown = 127;  // low contrast; never part of a component

struct ThresholdOptions {
  // The default profile's values, chosen by measurement (issue 17; README "Where the tags were lost"):
  // 2 px tiles keep the black border of a 12-24 px tag apart from its white ring (AprilTag 2/3 use 4,
  // which merges them: on 60 realistic frames 38 % vs 71 % of the 20-24 px tags), and a contrast floor
  // of 20/255 (libapriltag: 5/255) leaves flat texture unknown, which also makes the stage faster on
  // textured photographs (0.63 vs 0.77 of libapriltag d1's time on corpus images). The ray-traced
  // distance, blur and noise sweeps are unchanged by both. Session 6 measured 10/255: realistic set
  // (200 frames) 20-24 px tags 121 -> 129 of 188, all sizes 857 -> 907 of 1384 (below 10/255 nothing
  // more), but time / libapriltag d1 0.55 -> 0.95 on the realistic set and 0.61 -> 0.80 on the corpus.
  int tile_size = 2;                    // px, >= 1
  float min_contrast = 20.0f / 255.0f;  // max - min below this is flat: unknown
  // Relative contrast floor (beyond AprilTag 2/3; issue 17, shaded small tags of the realistic set):
  // a neighbourhood whose max - min is under min_contrast is still classed when max - min is at least
  // low_contrast (absolute) and at least weber_ratio x max (Weber contrast against the bright side).
  // A tag in shade or with grey ink has a small absolute but a large relative step; bright texture,
  // whose small steps are a small fraction of its brightness, stays flat (and so stays free).
  // Off when low_contrast >= min_contrast (the default), i.e. max - min < min_contrast is flat.
  float low_contrast = 20.0f / 255.0f;  // absolute floor of the relative test, >= 0
  float weber_ratio = 0.0f;             // (max - min) / max at least this, >= 0
  // The classing rule where the neighbourhood is not flat: 0 = against the midpoint of its min and
  // max (AprilTag 2/3); > 0 = against the local mean, the image blurred by a Gaussian of this sigma
  // (px). A 2-3 px white ring between a dark card and the black border of a small tag is lighter than
  // its local mean even when brighter ground a few pixels away lifts the midpoint above it.
  float mean_sigma = 0.0f;
};

// The classed image: one byte a pixel, values kTernaryDark, kTernaryLight or kTernaryUnknown.
struct TernaryImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> data;  // row-major
  std::uint8_t at(int x, int y) const {
    return data[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
  }
};

// Per-tile statistics, kept between frames (their storage only grows).
struct ThresholdScratch {
  std::vector<float> tile_min, tile_max, tmp_min, tmp_max;
  std::vector<float> tile_mid, mid;             // per tile, per column of the current tile row: the threshold
  std::vector<std::uint8_t> tile_flat, flat;    // per tile, per column: 0xFF where the tile is flat, else 0
  ImageF mean, mean_tmp;                        // ThresholdOptions::mean_sigma > 0: the local mean
};

// Classes every pixel of `img` into `out` (resized; storage reused). Throws std::invalid_argument
// for tile_size < 1 or a negative or non-finite min_contrast, low_contrast or weber_ratio.
void adaptive_threshold(const ImageF& img, const ThresholdOptions& opt, ThresholdScratch& scratch, TernaryImage& out);

// Convenience form with its own scratch (allocates per call).
TernaryImage adaptive_threshold(const ImageF& img, const ThresholdOptions& opt = {});

}  // namespace tagbench
