#pragma once
// Beyond the paper and AprilTag 3 (off in both profiles; measured in docs/default-profile.md,
// session 22): candidate quads from straight edges (line_segments.hpp, LSD's method) joined by the
// paper's quad search (quad_search.hpp). A small tag whose white ring is broken or classed with its
// border has no outline among the threshold stage's boundary groups, yet its four sides are short
// straight edges that region growing on gradient directions still finds whole.
//
// Each edge is searched both ways, so a quad may be dark inside (the black square) or light inside
// (a white ring's outer edge on a darker card), or mix the two where the ring is broken on one side;
// the caller reads every quad both as the black square and as a printed square (printed_square.hpp).
// Coordinates: pixel centres at integer coordinates; corners clockwise on screen (quad_search.hpp).
#include <span>
#include <vector>

#include "homography.hpp"
#include "image.hpp"
#include "line_segments.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct LineQuadOptions {
  bool enabled = false;      // both profiles off (see above)
  double max_side_px = 64;   // quads with a longer side are not kept: larger tags have their outline
  double min_side_px = 8;    // every side and diagonal at least this (QuadSearchOptions::min_tag_size)
  LineSegmentOptions segments;
};

struct LineQuadScratch {
  LineSegmentScratch segments;
  std::vector<Segment> both_ways;
};

// The quads of `img`'s edges within the size bounds whose centre lies inside none of `covered`
// (the corners of tags already found, any winding). Quads carry observed_perimeter 0: an inferred
// outline must not win duplicate ties against a tag's own quad.
std::vector<Quad> line_quads(const ImageF& img, std::span<const Corners> covered, const LineQuadOptions& opt,
                             LineQuadScratch& scratch);

}  // namespace tagbench
