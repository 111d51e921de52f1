#pragma once
// Beyond the paper and AprilTag 2: a quad fitted to a boundary group whose outline has a bump, i.e.
// a tag with part of one or more sides hidden by an object in front of it (fit_quad, quad_fit.hpp,
// fails there: no four runs of the outline are straight). The tag's square shape is used instead:
// its outline is four straight lines, and an occluder darker than the threshold only ADDS dark
// area outside the square (its outline is then an outward bump), so
//   1. the outline (points sorted by angle around the box centre) is split into straight runs
//      (Douglas-Peucker, `split_tolerance_px`);
//   2. runs on one line are merged (direction within `merge_angle_deg` unless the run is short,
//      together a line within `max_line_mse`, the run's centroid within `merge_distance_px` of it),
//      so a side visible on both sides of the occluder is one line;
//   3. of the (at most `max_lines`) lines with the most points, every set of four that makes a
//      convex quad (angles as fit_quad's) is scored: each side's points must cover at least
//      `min_side_fraction` of it (a side visible over 20 % of its length still fixes its line), the
//      four cover at least `min_total_coverage` sides in all, and the points off the four lines
//      (the occluder's outline) must lie outside the quad (at most `max_inside_outliers` of them
//      inside by more than the tolerance): an occluder cannot remove dark area;
//   4. the best set (most points on its lines) gives the corners: consecutive lines' intersections,
//      clockwise on screen (the Quad convention of quad_search.hpp);
//   5. if no set of four passes, sets of three well-covered sides, the fourth joining the far ends
//      of its neighbours (`three_sides`).
// Coordinates are in the pixels of the image the points came from (pixel centres at integers).
#include <optional>
#include <span>
#include <vector>

#include "angle_order.hpp"
#include "boundaries.hpp"
#include "homography.hpp"
#include "image.hpp"

namespace tagbench {

struct OccludedQuadFitOptions {
  // Points whose image gradient (dark to light) makes an angle with the direction from the group's
  // centre of more than acos(this) are left out: the square's own outline has its dark side inside;
  // when the occluder joins the square to a dark background, the group also holds the white ring's
  // outer outline, whose dark side is outside.
  double min_radial_cos = 0.3;
  // Smaller groups are not tried: most groups of a natural image are small, and this fit costs a
  // sort and a split per group (the speed of the default profile); 160 points is an outline of
  // about 60 px, a black square of about 15 px.
  int min_group_points = 160;
  double split_tolerance_px = 1.5;   // Douglas-Peucker: a run is straight when no point is further from its chord
  double merge_angle_deg = 8.0;      // two runs are one line when their directions differ by less ...
  double max_line_mse = 0.6;         // ... both together fit a line to this mean squared distance (px^2) ...
  double merge_distance_px = 1.0;    // ... and the run's centroid is this close to that line
  double inside_tolerance_px = 1.5;  // a point off the lines is inside the quad when further in than this
  int max_lines = 7;                 // candidate lines (most points first); C(7, 4) = 35 sets
  int max_runs = 24;                 // an outline of more straight runs is not a tag (textures): give up
  double min_side_fraction = 0.15;   // of each side's length covered by its points
  double min_total_coverage = 2.6;   // summed coverage of the four sides (4 = all fully visible)
  double min_on_lines = 0.6;         // fraction of the outline's points on the four lines
  double max_inside_outliers = 0.03; // fraction of the group's points off the lines and inside the quad
  // When no four lines pass: three lines each covering `min_three_side_coverage` of its side, the
  // fourth side joining the far ends of its neighbours' points (a side hidden but for short pieces).
  // Off: measured on tagbench raytrace conditions (occlusion 0.8, 50 trials) it found the 13 tags
  // the four-line fit misses, but 12 of 50 then had corners 1-3.5 px off (orientation 3-40 deg):
  // the far ends of the neighbours' points are not the corners well enough for occlusion_refit.
  bool three_sides = false;
  double min_three_side_coverage = 0.75;
};

struct OccludedQuadFitScratch {
  struct Pt {
    float x, y;
  };
  std::vector<std::uint64_t> order;  // the kept points by angle (angle_order.hpp)
  AngleSortScratch sort;
  std::vector<Pt> pts;               // in that order
  std::vector<int> vertices, stack;
  std::vector<int> line_of;  // per point: its candidate line, or -1
};

// The quad of a boundary group with an occluded part, or nullopt. `img` is the image the points
// came from (its gradient selects the points, see min_radial_cos); `min_angle_deg` and `min_area`
// (px^2) are fit_quad's filters. Dark squares on a light ground only.
std::optional<Corners> fit_quad_occluded(std::span<const BoundaryPoint> group, const ImageF& img, double min_angle_deg, double min_area,
                                         const OccludedQuadFitOptions& opt, OccludedQuadFitScratch& scratch);

}  // namespace tagbench
