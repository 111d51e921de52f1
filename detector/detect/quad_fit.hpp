#pragma once
// A quad fitted to each group of boundary points (beyond the paper; AprilTag 2, section III-C).
//
// Per group: the points are sorted by their angle around the group's bounding-box centre, which
// walks the outline once; a quad then splits that cyclic sequence into four runs, each fitted with
// a line. The split is chosen among "corner candidates": for every point, the error of one line
// fitted to the kernel of points around it (about half a short side long) is large where the
// outline bends, so its local maxima (at most max_maxima, the largest) are the candidates, and the
// four with the least total line-fit error win. Cumulative weighted moments make every line fit
// over any cyclic run O(1). Points are weighted by the image's gradient magnitude there (+ 1), so
// crisp edge points count more than blurred or noisy ones.
//
// Corners are the intersections of consecutive lines, in increasing angle around the centre, which
// with y down is clockwise on screen: the Quad convention of quad_search.hpp. Filters: enough points,
// the dark side inside (the gradient points outward on the whole), each line's mean squared error,
// the area, every corner's angle within [min_angle, 180 - min_angle] degrees, and convexity.
//
// Refit on one side's points (refit_one_side, beyond AprilTag 3): on a tag of 10-12 px the black
// border and the white ring are about one pixel wide and the threshold breaks them, so the border
// and the ground can become one dark component (or the ring and the light payload cells one light
// component). The pair's group then holds two outlines, e.g. the ring's outer edge (light inside)
// and the square's edge (dark inside), and no single quad fits it. When a group fails, the quad is
// fitted again to only the points whose dark-to-light step points away from the group's centre (for
// dark_inside; toward it for light_inside): the square's edge alone.
// Coordinates are in the pixels of the image the points came from (pixel centres at integers).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "angle_order.hpp"
#include "boundaries.hpp"
#include "image.hpp"
#include "outer_outline.hpp"
#include "quad_fit_occluded.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct QuadFitOptions {
  int min_points = 24;             // fewer boundary points cannot be a quad (AprilTag 3: min_cluster_pixels 24)
  int max_maxima = 10;             // corner candidates kept per group (AprilTag 3: max_nmaxima 10); C(10,4) = 210 splits
  double max_line_fit_mse = 10.0;  // px^2, per side and on average (AprilTag 3: max_line_fit_mse)
  double min_angle_deg = 10.0;     // every corner's angle in [min, 180 - min] (AprilTag 3: critical_rad 10 deg)
  double min_tag_width = 6.0;      // px: quads whose area is below 0.95 min_tag_width^2 are dropped
  bool dark_inside = true;         // accept dark squares on a light ground (every tagbench family)
  bool light_inside = false;       // accept light squares on a dark ground (reversed-border families)
  bool refit_one_side = false;     // a failed group is fitted again on its outward points (see above)
  // Beyond AprilTag 3: when every fit above and the occluded fit below fail on a dark-inside group,
  // fit again on its outer outline (outer_outline.hpp: the outward points outermost from the centre),
  // which drops the payload's inner edges a leaking white ring adds to the group; and when the
  // group's own fit succeeded but the outline leaves out outer.min_dropped of its points, add the
  // outline's quad as a second candidate; where the outline gives no quad either, its innermost
  // outward points when outer.innermost (a border run into a darker plate round the tag). Off here;
  // the default profile turns both on (DetectorOptions).
  bool refit_outer_outline = false;
  OuterOutlineOptions outer;
  // Beyond AprilTag 2: when the quad fit above fails on a dark-inside group, try fit_quad_occluded
  // (quad_fit_occluded.hpp: the square's four lines fitted robustly, an occluder's outline left out).
  // Off here (AprilTag 3 has no such step); the default profile turns it on (DetectorOptions).
  bool tolerate_occlusion = false;
  OccludedQuadFitOptions occluded;
};

struct QuadFitScratch {
  struct Pt {
    float x, y, w;  // position (px), weight
  };
  struct Moments {
    double mx, my, mxx, mxy, myy, w;
  };
  // The line fit of the run between corner candidates a and b (entry a * candidates + b), made
  // when the search over sets of four first needs it: that search meets each run up to dozens of
  // times (a fit of 10 candidates tries up to 210 sets).
  struct RunFit {
    double mse, err;         // mean squared distance, and that times the run's point count
    double cx, cy, nx, ny;   // the line: weighted centroid and unit normal
    bool done;
  };
  std::vector<std::uint64_t> order;  // the points by angle (angle_order.hpp: angle_key of the group's index)
  AngleSortScratch sort;
  std::vector<Pt> pts;                // the group's points in that order
  std::vector<Moments> cum;
  std::vector<RunFit> runs;
  std::vector<double> err, smooth;
  std::vector<int> maxima;
  std::vector<BoundaryPoint> side;  // refit_one_side: the group's points on one side
  OuterOutlineScratch outer;        // refit_outer_outline
  OccludedQuadFitScratch occluded;
};

// One group's quad, or nullopt when a filter rejects it. `img` supplies the gradient weights and
// the size limit (a group of more than 2 (2 w + 2 h) points is bigger than any outline in it).
std::optional<Corners> fit_quad(std::span<const BoundaryPoint> group, const ImageF& img, const QuadFitOptions& opt,
                                QuadFitScratch& scratch);

// The points of `group` whose step toward the light side points away from (outward = true) or toward
// the centre of the group's bounding box, into `out` (cleared first).
void one_side_points(std::span<const BoundaryPoint> group, bool outward, std::vector<BoundaryPoint>& out);

// A fitted quad as a candidate: these corners, segments -1, observed_perimeter their perimeter.
Quad fitted_quad(const Corners& corners);

// The outline fallbacks' fit (fit_quads; dark_outlines.hpp): fit_quad on `outline` (e.g. the points
// outer_outline_points left in s.side), refused unless it passes outline_has_ring when
// opt.outer.ring_check.
std::optional<Corners> fit_outline(std::span<const BoundaryPoint> outline, const ImageF& img, const QuadFitOptions& opt,
                                   QuadFitScratch& s);
// The innermost outward outline of the group of the last outer_outline_points call on s.outer (into
// s.side, inner_outline_points) fitted by fit_outline, when it holds at least 8 points of which under
// 80 % are also on the outer outline (else it is the same outline again): a square whose border ran
// into a darker plate.
std::optional<Corners> fit_innermost_outline(const ImageF& img, const QuadFitOptions& opt, QuadFitScratch& s);

// Every group's quad appended to `out` (observed_perimeter = the quad's perimeter, segments = -1).
// With `gave_quad`: resized to the groups' count, 1 where the group gave at least one quad, else 0.
void fit_quads(const BoundaryGroups& groups, const ImageF& img, const QuadFitOptions& opt, QuadFitScratch& scratch,
               std::vector<Quad>& out, std::vector<std::uint8_t>* gave_quad = nullptr);

namespace detail {
// The quad fit's kernel line-fit errors (corner_candidates): for i in [lo, hi), err[i] = (2k + 1) x the
// small eigenvalue of the covariance of points i - k .. i + k, from the cumulative moments
// (cum[i + k] - cum[i - k - 1]; so lo >= k + 1). The same numbers whether or not SSE2 takes two at a time.
void kernel_errors(const QuadFitScratch::Moments* cum, int k, int lo, int hi, double* err);
}  // namespace detail

}  // namespace tagbench
