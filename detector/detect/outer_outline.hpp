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
// And when the outermost outline gives no quad: the innermost outward points instead
// (inner_outline_points; OuterOutlineOptions::innermost). A tag on a plate or card darker than its
// paper has only the 1-cell white ring between its black border and the plate; seen at a slant the
// ring is 1-2 px, and where the threshold breaks it the border's dark component runs into the plate.
// The group (that dark component against the ring, which leaks out to the ground) then holds the
// square's edge, the plate's inner edge (inward steps: dropped by filter 1) and the plate's outer edge
// (outward, further out: the outermost outline takes it). The square's edge is the innermost outward
// outline; the payload's inner edges would be innermost, but a payload's light cell is its own light
// component, another group, unless the ring leaks into it as well.
// Coordinates: BoundaryPoint's doubled pixels (boundaries.hpp); the centre is the outward points'
// bounding-box centre.
#include <limits>
#include <span>
#include <vector>

#include "boundaries.hpp"
#include "image.hpp"
#include "homography.hpp"

namespace tagbench {

struct OuterOutlineOptions {
  int bins = 96;            // angular bins around the centre, 8..1024 (about 1.3 px of arc at 20 px out)
  double tolerance = 0.15;  // kept: distance >= (1 - tolerance) x the bin envelope's, in (0, 1)
  // quad_fit.hpp's use: when the group's own fit succeeded, the outer outline's quad is added as a
  // second candidate if the outline left out at least this fraction of the group's points, [0, 1],
  // and its quad differs from the first by more than min_corner_change_px at some corner (>= 0).
  double min_dropped = 0.1;
  double min_corner_change_px = 1.0;
  // Only groups whose bounding box's longer side is at most this many px (of the image the groups
  // come from) are tried, > 0; infinity tries every group. The fallback is for small tags, whose ring
  // is 2-3 px wide; on natural images most groups are large texture outlines, where it costs the
  // most (their many points) and never finds a tag the group's own fit missed.
  double max_size_px = std::numeric_limits<double>::infinity();
  // Which groups are worth the outline (quad_fit.hpp's use): tried only when the group holds at least
  // this many boundary points per px of its bounding box's width plus height, >= 0 (0: every group).
  // One closed outline, such as a plain square's, gives about 4; the outline finds tags whose group
  // holds inner edges beside the square's (the payload's, the ring's outer edge), so more. Most groups
  // tried are texture outlines and lines, each costing an outline, a fit, the ring check and often an
  // edge refinement, a decoding and a second look. A count over a length: the same at every scale (the
  // second look's crops are resampled) and for a tag seen edge-on (a thin box) as face-on.
  double min_points_per_box_px = 0;
  // The ring check (quad_fit.hpp's use; outline_has_ring below): an outline's quad is kept only when
  // it looks like a dark square inside a light ring. Most failed groups of a natural image give an
  // outline quad that is not a tag, and each quad costs an edge refinement and a decode (most of the
  // fallback's time): the check throws those away for 32 samples.
  bool ring_check = false;
  double ring_min_share = 0.75;        // of each side's sample pairs, at least this share must step up, [0, 1]
  double ring_min_step = 3.0 / 255.0;  // and the mean step (ring - border) of all at least this, >= 0
  double min_side_ratio = 0.3;         // shortest side / longest side at least this, [0, 1]
  // Each pair read also this fraction of the quad's width further out, the larger step counting
  // (0: off), [0, 0.25]: the threshold's outline of a blurred 1-cell border with light payload cells
  // behind it can lie a pixel or two inside the square's edge, where the inner sample reads a light
  // cell. Off here; 1/16 on at most one side in the default profile since session 37
  // (default_profile_threshold_quads, detector_options.hpp; variant keys `ring_slack`,
  // `ring_slack_sides`).
  double ring_outward_slack = 0;
  int ring_slack_sides = 4;  // at most this many sides pass only through the slack, 0..4
  // threshold_quads.hpp's use: whether the refit also runs when quads are found at half resolution.
  // Off: there a 20 px tag is 10 px and its ring 1-1.5 px, and the refit cost the half-resolution
  // profile 0.84 -> 1.03 of libapriltag d2's time on the realistic set (target <= 1.0).
  bool at_half_resolution = false;
  // quad_fit.hpp's use: when the outermost outline gives no quad (none fitted, or refused by the ring
  // check), fit the innermost outward points (inner_outline_points), unless at least 80 % of them are
  // outermost too (the same points, the same failed fit), under the same ring check. Off here; the
  // default profile turns it on (detector_options.hpp).
  bool innermost = false;
  // Only when the outward points surround the centre: they fall into at least this share of the
  // angular bins, [0, 1]. On the realistic set the groups whose innermost outline gave a tag covered
  // 84-100 % of the bins; 0.75 leaves about 7 % of the groups that reach this step.
  double innermost_min_coverage = 0.75;
};

struct OuterOutlineScratch {
  std::vector<BoundaryPoint> side;
  std::vector<float> radius;
  std::vector<int> bin;
  std::vector<float> envelope, widened;
  std::vector<float> inner_envelope, inner_widened;  // inner_outline_points
};

// The angular bin of (dx, dy) about the centre: exactly min(bins - 1, int((atan2f(dy, dx) + pi_f) x
// per_radian)) in float arithmetic (per_radian = bins / (2 pi_f), as outer_outline_points computes it),
// mostly without the atan2f call (a polynomial, the call only within 1e-3 of a bin's edge).
int angle_bin(float dx, float dy, int bins, float per_radian);

// The outward, outermost points of `group` into `out` (cleared first); out may be empty. Empty too
// when fewer than `min_points` points face outward (the outline, a subset of them, could not give a
// quad: most groups of a textured ground end here, before the angles and distances are computed).
void outer_outline_points(std::span<const BoundaryPoint> group, const OuterOutlineOptions& opt,
                          OuterOutlineScratch& scratch, std::vector<BoundaryPoint>& out, std::size_t min_points = 0);

// The innermost of the outward points of the last outer_outline_points call on `scratch` (its centre
// and angular bins; a point is kept when its distance from the centre is at most (1 + tolerance)
// times the smallest in its bin and the two bins beside it) into `out` (cleared first; empty when
// that call kept nothing, or when its outward points fall into fewer than innermost_min_coverage of
// the bins). Returns how many of them that call's outline also kept.
std::size_t inner_outline_points(const OuterOutlineOptions& opt, OuterOutlineScratch& scratch,
                                 std::vector<BoundaryPoint>& out);

// Whether the quad `q` (corners in order around it, px, pixel centres at integers) of `img` is darker
// just inside each side than just outside: 4 samples a side (at 0.2, 0.4, 0.6, 0.8 of it), each a pair
// 1/16 of the quad's width inward (the black border's cells: 1/8 of a 36h11 square, 1/6 of 16h5's)
// and 1/16 outward (the white ring's), placed by the corners' bilinear map, read bilinearly. True
// when on every side at least ring_min_share of the 4 pairs are lighter outside, the mean step
// (outside - inside) of the 16 is at least ring_min_step, and the shortest side is at least
// min_side_ratio of the longest.
bool outline_has_ring(const Corners& q, const ImageF& img, const OuterOutlineOptions& opt);

}  // namespace tagbench
