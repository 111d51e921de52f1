#pragma once
// Fitting a directed line segment to each cluster (paper section III-A, Fig. 3; min line length 4 px:
// docs/paper-to-code.md section 1).
//
// Conventions: x right, y down, pixel centres at integer coordinates (see image.hpp).
//
// Fit: weighted least squares with weight w_i = the pixel's gradient magnitude as stored by
// compute_gradients, i.e. the SQUARED magnitude Ix^2 + Iy^2. The line passes through the weighted
// centroid along the principal eigenvector of the weighted 2x2 covariance (total least squares:
// perpendicular distances). The ends are the centroid plus the smallest and largest projections
// of the cluster's pixel centres onto that direction, so the segment spans the cluster.
//
// Orientation ("dark on the left"): the gradient points from dark to light. In image
// coordinates (y down) the left-hand side of a walk along direction d = (dx, dy), as seen on
// screen, is (dy, -dx) and the right-hand side is (-dy, dx). The light side must be on the right,
// so p0 -> p1 is chosen such that
//     sum_i w_i * cross(d, g_i) > 0,   cross(d, g) = dx * gy - dy * gx,  g_i = (cos theta_i, sin theta_i),
// i.e. d is the mean gradient direction turned by -pi/2 (theta_segment ~ theta_gradient - pi/2).
// Consequence: walking around a dark blob on a light background the segments go counter-clockwise
// on screen, and each turn from one side to the next has cross(d_k, d_k+1) < 0 in image
// coordinates (turning angles sum to about -2 pi: the winding range [-7, -5] of docs/paper-to-code.md section 1).
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "segmentation.hpp"

namespace tagbench {

struct Segment {
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero();  // start, dark side on the left walking to p1
  Eigen::Vector2d p1 = Eigen::Vector2d::Zero();  // end
  double theta = 0.0;                            // direction of p1 - p0, atan2(dy, dx) in (-pi, pi]
  double length = 0.0;                           // |p1 - p0|
};

struct LineFitOptions {
  double min_length = 4.0;  // Java default (docs/paper-to-code.md section 1), in pixels of the image the clusters came from
};

// The directed segment of one cluster; nullopt when the cluster is empty or has zero total weight.
std::optional<Segment> fit_segment(std::span<const ClusterPixel> pixels);

// fit_segment for every cluster, keeping segments with length >= min_length, in cluster order.
std::vector<Segment> fit_segments(const Clusters& clusters, const LineFitOptions& opt = {});

// A segment found on the half-resolution image (blur.hpp) in full-resolution coordinates:
// each end p -> 2 p + (0.5, 0.5), length doubled, direction unchanged.
Segment segment_full_from_half(const Segment& s);

}  // namespace tagbench
