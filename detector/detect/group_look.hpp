#pragma once
// A look at the boundary groups that gave no quad (beyond AprilTag 2/3; issue 17, session 10: small
// low-contrast tags of the realistic set). The second look (second_look.hpp) re-classes the region of a
// quad that did not decode; a tag whose white ring the 6 px local threshold broke, whose black square
// leaked into the dark ground, or whose ring was classed dark often gives NO quad at all: only
// fragments (the ring's piece against the leaked ground, a payload cell against the border) whose
// boundary groups fail the quad fit. Here each such group of tag size marks a window (its bounding box,
// widened to at least min_window_px around its centre); windows whose centre lies inside a quad the
// main pass found (decoded or second-looked already) or inside an earlier window are skipped. The
// windows are handed to second_look_quads as axis-aligned pseudo-quads: one Otsu threshold of the
// window's pixels, the threshold stage's components, boundaries and fit, refined on the image.
//
// Coordinates: pixels of the full-resolution image (pixel centres at integers); BoundaryGroups in
// doubled pixels (boundaries.hpp). Runs only where the groups were found at full resolution.
#include <span>
#include <vector>

#include "boundaries.hpp"
#include "image.hpp"
#include "quad_search.hpp"
#include "second_look.hpp"
#include "threshold_quads.hpp"

namespace tagbench {

struct GroupLookOptions {
  bool enabled = false;        // off here; the default profile's value is in detector.hpp
  double min_size_px = 8;      // groups whose bounding box's longer side is in [min, max] px, >= 0
  double max_size_px = 40;     //   (a 20-24 px tag's ring piece or its payload cells' outline), > 0
  int min_points = 24;         // and that have at least this many boundary points, >= 1
  double min_window_px = 32;   // the window is at least this across, centred on the group's box, > 0
  double margin_px = 3;        // and the box grown by this on every side, >= 0
  int max_windows = 200;       // at most this many windows an image (raster order of the groups), >= 0
};

// Windows (axis-aligned pseudo-quads, corners clockwise on screen, pixel centres at integers, clipped
// to [0, width-1] x [0, height-1]) for the groups of `groups` that no quad of `found` covers.
std::vector<Quad> group_look_windows(const BoundaryGroups& groups, std::span<const Quad> found, int width, int height,
                                     const GroupLookOptions& opt);

// The group look's new quads on `gray`: the windows of the groups that none of these covers: the
// quads of the main pass that decoded (looked[i] false), those the second look saw (looked[i] and
// at most second.max_size_px across) and the second look's quads `again`; each window classed by
// second_look_quads (one Otsu threshold, the stage's components, boundaries, fit and refinement).
std::vector<Quad> group_look_quads(const ImageF& gray, const BoundaryGroups& groups, std::span<const Quad> quads,
                                   const std::vector<bool>& looked, std::span<const Quad> again,
                                   const ThresholdQuadOptions& threshold, const SecondLookOptions& second,
                                   const GroupLookOptions& opt);

}  // namespace tagbench
