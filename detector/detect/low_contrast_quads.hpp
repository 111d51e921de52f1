#pragma once
// A low-contrast look of the threshold quad stage (beyond AprilTag 2/3; issue 17, small tags in shade
// or with grey ink on the realistic set). The adaptive threshold (threshold.hpp) leaves a pixel
// unknown when its window (3 x 3 tiles) spans less than min_contrast (20/255); a tag whose black
// border and white ring differ by 5-20 grey levels is then mostly unknown and gets no candidate quad
// (session 9: 68 of the 184 realistic tags readable from their true corners but without a quad). A
// lower floor for the whole image finds them but classes all faint texture too, at about 75 % more
// time. Here the faint places are found first, on the tile grid: the tiles whose window spans
// [min_contrast, the main floor) form 8-connected regions, and only a region no larger than a small
// tag (its box at most max_size_px + 2 windows across) is looked at: its box, grown by margin_px, is
// thresholded with the low floor, and the crop's components, boundaries and quad fit (the stage's
// own) give candidates, kept only when a lighter ring surrounds them (outline_has_ring,
// outer_outline.hpp). A faint tag on faint texture (one large region) is not looked at. The decoder
// judges every candidate.
//
// Coordinates: pixels of the image the quads are found on (pixel centres at integers); quads as in
// quad_search.hpp.
#include <vector>

#include "boundaries.hpp"
#include "components.hpp"
#include "image.hpp"
#include "quad_fit.hpp"
#include "quad_search.hpp"
#include "threshold.hpp"

namespace tagbench {

struct LowContrastPassOptions {
  bool enabled = false;                 // off here; the default profile turns it on (detector_options.hpp)
  float min_contrast = 10.0f / 255.0f;  // the low floor, [0, 1]; below the main floor (else nothing runs)
  double max_size_px = 48;              // regions whose box's longer side is at most this + 2 windows, > 0 (default profile: 64)
  double min_size_px = 16;              // and at least this, >= 0
  // A region must fill at least min_fill of its box with faint tiles and cover min_area_px: a faint
  // tag is a compact patch (its border, ring and payload all have some contrast), most faint texture
  // specks are thin or small (realistic set: 380 regions a frame without these filters, 21 with
  // them; 160 px area: 37 regions, which cost +20 % of the default profile's time against +9 %, for
  // 1 tag more of 1384).
  double min_fill = 0.35;               // [0, 1]
  double min_area_px = 240;             // >= 0
  double min_aspect = 0.3;              // the box's shorter side / longer side at least this (not a line), [0, 1]
  double margin_px = 3;                 // the crop: the region's box grown by this, >= 0
  // The main fit's fallbacks (quad_fit.hpp) in the regions too: the occlusion-tolerant fit and the
  // outer outline.
  bool occlusion_fit = false;
  bool outer_outline = true;
  bool ring_check = true;               // keep only quads with a lighter ring around (outline_has_ring)
  // Whether it also runs when quads are found at half resolution (ThresholdQuadOptions::halve).
  bool at_half_resolution = false;
};

// A region of faint tiles: its box in pixels (inclusive).
struct FaintRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int tiles = 0;  // faint tiles in it
};

struct LowContrastScratch {
  TernaryImage tiles;                 // faint_regions: the band's tiles (light) and the rest (unknown)
  ComponentScratch tile_scratch;
  Components tile_components;
  std::vector<FaintRegion> boxes;     // per component id: its box in tiles
  std::vector<FaintRegion> regions;
  ImageF crop;
  BoundaryPassScratch pass;  // threshold, components, boundaries of one crop
  std::vector<Quad> found;
};

// The faint regions of a width x height image whose adaptive threshold (tile_size) left its window
// min / max per tile in `windows` (ThresholdScratch::tile_min, tile_max after adaptive_threshold):
// 8-connected tiles whose window spans [low, high), kept when their box (px) has its longer side in
// [opt.min_size_px, opt.max_size_px + 2 windows] and passes opt.min_fill and opt.min_area_px; into
// `out` (cleared first), in raster order of their first tile.
void faint_regions(const ThresholdScratch& windows, int width, int height, int tile_size, float low, float high,
                   const LowContrastPassOptions& opt, LowContrastScratch& scratch, std::vector<FaintRegion>& out);

// Appends to `out` the quads found in the faint regions of `img` (`windows`: the main pass's threshold
// scratch on `img`; `threshold`, `dark_eight`, `boundaries` and `fit`: the main pass's options).
void low_contrast_quads(const ImageF& img, const ThresholdScratch& windows, const ThresholdOptions& threshold, bool dark_eight,
                        const BoundaryOptions& boundaries, const QuadFitOptions& fit, const LowContrastPassOptions& opt,
                        LowContrastScratch& scratch, QuadFitScratch& fit_scratch, std::vector<Quad>& out);

}  // namespace tagbench
