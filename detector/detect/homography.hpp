#pragma once
// Homography by the normalised Direct Linear Transform (paper section III-C; Hartley & Zisserman).
//
// A homography H maps plane points to image points in homogeneous coordinates: p_img ~ H [x y 1]^T.
// For a tag, the plane is the tag's own frame scaled so that the black square is [-1, 1]^2: x toward
// the tag's right edge, y toward its bottom edge (as printed), so the corners are
// top-left (-1,-1), top-right (1,-1), bottom-right (1,1), bottom-left (-1,1). Image points use pixel
// centres at integer coordinates (OpenCV's convention).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <Eigen/Core>
#include <Eigen/Geometry>  // homogeneous(), hnormalized()

namespace tagbench {

using Corners = std::array<Eigen::Vector2d, 4>;  // top-left, top-right, bottom-right, bottom-left

// Twice a quad's signed area (shoelace; positive for clockwise on screen with y down), and its
// perimeter, each summed over the sides in corner order.
inline double twice_signed_area(const Corners& q) {
  double area2 = 0;
  for (std::size_t i = 0; i < 4; ++i) area2 += q[i].x() * q[(i + 1) & 3].y() - q[(i + 1) & 3].x() * q[i].y();
  return area2;
}
inline double perimeter(const Corners& q) {
  double p = 0;
  for (std::size_t i = 0; i < 4; ++i) p += (q[(i + 1) & 3] - q[i]).norm();
  return p;
}

// The homography taking from[i] to to[i] (at least 4 pairs, no 3 of the first 4 collinear) by the
// normalised DLT: each point set is shifted to its centroid and scaled to mean distance sqrt(2),
// the null vector of the 2N x 9 system is found by SVD, then the scaling is undone. H is scaled so
// that its Frobenius norm is 1 and H(2,2) >= 0. nullopt when the points are degenerate.
std::optional<Eigen::Matrix3d> homography_dlt(std::span<const Eigen::Vector2d> from,
                                              std::span<const Eigen::Vector2d> to);

// The tag homography: the square [-1,1]^2 (corners as above) onto the four image corners.
std::optional<Eigen::Matrix3d> tag_homography(const Corners& image_corners);

// H applied to a point, with the homogeneous division.
// Inline: the payload readers map hundreds of points per quad through it.
inline Eigen::Vector2d apply_homography(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}

#if defined(__SSE2__)
// apply_homography at the two points (u[0], v[0]) and (u[1], v[1]) into (x[k], y[k]): each lane
// (H00 u + H01 v) + H02 over (H20 u + H21 v) + H22, the operations and order of apply_homography,
// so the same doubles (tests/test_homography.cpp).
inline void apply_homography_pair(const Eigen::Matrix3d& H, __m128d u, __m128d v, __m128d& x, __m128d& y) {
  const auto row = [&](int r) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_set1_pd(H(r, 0)), u), _mm_mul_pd(_mm_set1_pd(H(r, 1)), v)),
                      _mm_set1_pd(H(r, 2)));
  };
  const __m128d z = row(2);
  x = _mm_div_pd(row(0), z);
  y = _mm_div_pd(row(1), z);
}
#endif

// Whether p lies inside the convex quad q (either winding); a point on a side counts as inside. False
// when a NaN is involved and when all four corners lie on one line (no inside to speak of).
bool inside_quad(const Corners& q, const Eigen::Vector2d& p);

// inside_quad for many points of one quad along rows (a pixel scan): the sides' vectors once per
// quad and each side's row term once per row (inside_quad is this for one point). row(y) first, then
// contains(x) for points (x, y).
class QuadRowTest {
 public:
  explicit QuadRowTest(const Corners& q) : q_(q) {
    for (std::size_t i = 0; i < 4; ++i) e_[i] = q[(i + 1) % 4] - q[i];
  }
  void row(double y) {
    for (std::size_t i = 0; i < 4; ++i) a_[i] = e_[i].x() * (y - q_[i].y());
  }
  bool contains(double x) const {
    int pos = 0, on = 0;  // sides with the point on their left (or on them); sides whose line it lies on
    for (std::size_t i = 0; i < 4; ++i) {
      const double z = a_[i] - e_[i].y() * (x - q_[i].x());
      if (std::isnan(z)) return false;  // a NaN compares false, which would read as "right of every side"
      pos += z >= 0 ? 1 : 0;
      on += z == 0 ? 1 : 0;
    }
    return (pos == 4 || pos == 0) && on < 4;  // on all four lines: the corners lie on one line
  }

 private:
  Corners q_;
  std::array<Eigen::Vector2d, 4> e_;
  std::array<double, 4> a_{};
};

// A quad's corners re-ordered so that its corner `rotation` (0..3) comes first: the printed order
// TL, TR, BR, BL of a code read through the quad in that rotation (decode_quads.hpp).
Corners printed_corners(const Corners& quad, int rotation);

// The shortest and the longest side of a quad (px).
std::pair<double, double> side_length_range(const Corners& quad);

// The unit-square corners in the order above.
const Corners& tag_square_corners();

// The largest distance between corresponding corners when a[(k + shift) % 4] stands for b[k], px
// (shift 0..3: the same quad found from another starting corner).
inline double max_corner_distance(const Corners& a, const Corners& b, int shift = 0) {
  double worst = 0;
  for (int k = 0; k < 4; ++k)
    worst = std::max(worst, (a[static_cast<std::size_t>((k + shift) % 4)] - b[static_cast<std::size_t>(k)]).norm());
  return worst;
}

}  // namespace tagbench
