#pragma once
// Beyond the paper: sub-pixel refinement of a quad's four sides on the UNBLURRED image, once the quad
// is known. The paper's corners are the intersections of lines fitted to gradient clusters of the
// blurred image (line_fit.hpp); on small tags (cells of 1.5-3 px) the blur and the cluster's extent
// bias those lines by a large fraction of a cell, enough to sample the payload's outer cells on
// their neighbours. Here each side is re-located where the image itself has its dark-to-light step.
//
// Method: a quad's sides run clockwise on screen (quad_search.hpp), the black square inside, so the
// intensity grows along each side's outward normal n. At `samples` points spread over the side (not
// at its ends, where the neighbouring side's edge interferes) the profile I(p + s n) is scanned for
// s in [-range, range] (bilinear samples, pixel centres at integer coordinates); the derivative is
// the central difference over +-`derivative_half_px`, negative values (a light-to-dark step: the
// black border's inner edge, other objects) are ignored, and the edge's offset is the mean of s
// weighted by the squared derivative. The side's new line is the total-least-squares fit to the
// edge points (each weighted by its summed squared derivative); the corners are the new lines'
// intersections. Units: pixels throughout.
//
// One unit for both candidate stages: the paper's quads (gradient clusters of a blurred image) and
// the threshold quads (threshold_quads.hpp: boundaries quantised to half pixels, whole pixels when
// halving). Tried and dropped: the offset of the derivative's maximum (parabola-refined) as a
// gamma-free locator; on a gamma-encoded blurred step the encoding's steep dark end moves the
// maximum further toward the dark side than it moves the weighted mean (1.0 px vs 0.43 px RMS).
//
// The whole is repeated `iterations` times, each pass scanning around the previous pass's lines.
//
// Safeguards: a side with fewer than 3 located points keeps its old line; the whole refinement is
// rejected (nullopt) when a corner would move by more than `max_corner_shift_px` or the new quad is
// not convex, so a caller keeps the quad it had.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "homography.hpp"
#include "image.hpp"

namespace tagbench {

struct EdgeRefineOptions {
  // Search range along the normal, px: a third of a tag cell at most would be ideal, but the
  // corner error to correct is up to about a pixel, so at least `min_range_px`.
  double min_range_px = 1.0;
  double range_cell_fraction = 0.45;  // range = max(min_range_px, this x the cell size) ...
  double max_range_px = 2.5;          // ... capped here
  double step_px = 0.25;              // scan step along the normal
  double derivative_half_px = 0.5;    // central difference I(s + h) - I(s - h)
  double sample_spacing_px = 1.5;     // points along a side: about one per this many pixels ...
  int min_samples = 6;                // ... at least this many
  double end_margin = 0.1;            // fraction of the side left out at each end
  double max_corner_shift_px = 3.0;   // a larger move rejects the refinement
  // Intensities are raised to this power before the profile is differentiated: 2.2 undoes the
  // encoding gamma of ordinary (sRGB-like) cameras, whose dark-to-light step is otherwise lopsided
  // and its steepest point shifted toward the dark side once blurred; 1 = the image as it is (linear,
  // e.g. ray-traced frames).
  double gamma = 1.0;
  int iterations = 2;                 // passes; each re-centres the scan on the previous pass's lines,
                                      // so an edge near the end of the range is not biased inward
  int cells_across = 8;               // cells across the black square (d + 2; 36h11: 8): the cell size sets the range
};

// Buffers kept from one quad to the next (storage only grows): the located edge points of a side,
// the scan's steps and one scan's samples.
struct EdgeRefineScratch {
  struct Step {
    double s, hi, lo;  // offset along the normal and the two offsets the derivative samples (s +- h)
    int lo_from;       // the earlier step whose `hi` equals this `lo` (its sample is reused), or -1
  };
  std::vector<Eigen::Vector3d> points;       // (x, y, weight) of one side
  std::vector<Step> steps;                   // the scan of the current side, the same at every point
  std::vector<float> value;                  // per step: the intensity at `hi` (scan inside the image) ...
  std::vector<std::optional<float>> value_or_none;  // ... or nullopt outside it (scan crossing the border)
};

// The quad's corners (clockwise on screen, as quad_search gives them) refined on `img`; nullopt when
// the refinement is rejected (see above).
std::optional<Corners> refine_quad_edges(const ImageF& img, const Corners& corners, const EdgeRefineOptions& opt = {});
// The same with caller-owned buffers (no allocation once they have grown); identical results.
std::optional<Corners> refine_quad_edges(const ImageF& img, const Corners& corners, const EdgeRefineOptions& opt,
                                         EdgeRefineScratch& scratch);

namespace detail {
// value[j] = sample_bilinear_inside(img, p + steps[j].hi * n) (payload_decode.hpp) for every step,
// bit for bit (two steps at a time where SSE2 is there). Every point must lie inside the image
// ([0, w - 1] x [0, h - 1]); value holds steps.size() floats.
void sample_scan(const ImageF& img, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
                 const std::vector<EdgeRefineScratch::Step>& steps, float* value);
}  // namespace detail

}  // namespace tagbench
