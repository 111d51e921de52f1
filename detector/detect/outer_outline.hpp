#pragma once
// The outer outline of a boundary group (beyond AprilTag 2/3; issue 17, small tags of the realistic
// set): on a 20-28 px tag of low contrast the white ring is 2-3 px wide and the threshold often
// breaks it or the black border, so the ring's light component leaks into the payload's light
// cells (or the border's dark component into the dark ground). The pair's group then holds, beside
// the square's edge, the payload's inner edges (or the ring's outer edge), and no single quad fits
// it. The square's edge is what is left after two filters:
//   1. the points whose dark-to-light step points away from the group's centre (a dark square on a
//      light ground; the ring's outer edge, light inside, drops out: one_side_points, quad_fit.hpp);
//   2. of those, the outermost seen from the centre: the points are binned by their angle around
//      the centre, and a point is kept when its distance from the centre is at least
//      (1 - tolerance) times the largest distance in its bin and the two bins beside it. The payload's
//      inner edges lie at most 3/4 of the way out (one cell of the 8 of a 36h11 black square, 1/6 of
//      16h5's), the square's edge all the way: a convex quad seen from a point inside it.
// Coordinates: BoundaryPoint's doubled pixels (boundaries.hpp); the centre is the outward points'
// bounding-box centre.
#include <span>
#include <vector>

#include "boundaries.hpp"

namespace tagbench {

struct OuterOutlineOptions {
  int bins = 96;            // angular bins around the centre, 8..1024 (about 1.3 px of arc at 20 px out)
  double tolerance = 0.15;  // kept: distance >= (1 - tolerance) x the bin envelope's, in (0, 1)
  // quad_fit.hpp's use: when the group's own fit succeeded, the outer outline's quad is added as a
  // second candidate if the outline left out at least this fraction of the group's points, [0, 1],
  // and its quad differs from the first by more than min_corner_change_px at some corner (>= 0).
  double min_dropped = 0.1;
  double min_corner_change_px = 1.0;
};

struct OuterOutlineScratch {
  std::vector<BoundaryPoint> side;
  std::vector<float> radius;
  std::vector<int> bin;
  std::vector<float> envelope, widened;
};

// The outward, outermost points of `group` into `out` (cleared first); out may be empty.
void outer_outline_points(std::span<const BoundaryPoint> group, const OuterOutlineOptions& opt,
                          OuterOutlineScratch& scratch, std::vector<BoundaryPoint>& out);

}  // namespace tagbench
