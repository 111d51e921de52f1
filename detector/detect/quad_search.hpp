#pragma once
// Quad search (paper section III-B): depth-4 depth-first search over directed segments.
//
// Segments run with the dark side on their left (line_fit.hpp), so around a dark square they go
// counter-clockwise on screen and every turn has cross(d_k, d_k+1) < 0 in image coordinates.
// Depth 1 tries every segment; depths 2-4 try the segments that start "close enough" to where the
// previous one ended (a 2D lookup grid of segment starts answers that), turn the right way, and are
// not used yet; the fourth must end close enough to the first one's start, and the four turning
// angles must sum to one consistent turn ([-7, -5] rad: docs/paper-to-code.md section 1). Corners are the intersections of the
// fitted lines, so they are accurate to a fraction of a pixel.
//
// Output corners are in the tag's corner order convention for a quad read with its first corner as
// the printed top-left: clockwise on screen (top-left, top-right, bottom-right, bottom-left when
// upright). Which corner really is the printed top-left is decided by the decoder's rotation.
#include <vector>

#include "homography.hpp"
#include "line_fit.hpp"

namespace tagbench {

// The "close enough" rule: the search radius around a segment's end for the next segment's start.
enum class CloseEnoughRule {
  kPaper2011,  // 2 x length + 5 px (the paper)
  kCode2010,   // 0.5 x length (the 2010 Java code)
  kCode2012,   // 6 + 0.5 x length (the 2012 Java code)
};

struct QuadSearchOptions {
  CloseEnoughRule close_enough = CloseEnoughRule::kPaper2011;
  double min_tag_size = 6.0;       // px: every side and both diagonals at least this long (Java default: docs/paper-to-code.md section 1)
  double max_aspect = 32.0;        // longest side / shortest side (Java default: docs/paper-to-code.md section 1)
  double winding_min = -7.0, winding_max = -5.0;  // sum of the four turning angles, radians (Java: docs/paper-to-code.md section 1)
  double grid_cell = 10.0;         // px, lookup grid cell (Java default: docs/paper-to-code.md section 1)
  std::size_t max_quads = 200000;  // a hard cap so adversarial images cannot explode the search
  // Beyond the paper: each segment must lie on its own side of the quad (the side runs the segment's
  // way, dark on the left, and the segment's midpoint projects between the side's two corners). The
  // paper's generous radius otherwise joins lines of unrelated objects into thousands of quads per
  // frame; a real side, even partly occluded, always satisfies this. Checked as early as the corners
  // are known (from depth 2), which also prunes the search.
  bool segments_on_sides = true;
};

struct Quad {
  Corners corners;                // clockwise on screen, see above
  std::array<int, 4> segments{};  // indices into the segment list, in search order
  double observed_perimeter = 0;  // summed lengths of the four segments (for duplicate suppression)
};

double close_enough_radius(CloseEnoughRule rule, double length);

// The intersection of the lines through a and b; nullopt when (nearly) parallel.
std::optional<Eigen::Vector2d> line_intersection(const Segment& a, const Segment& b);

std::vector<Quad> find_quads(const std::vector<Segment>& segments, const QuadSearchOptions& opt = {});

}  // namespace tagbench
