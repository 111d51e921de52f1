#pragma once
// A tag folded along its vertical centre line (u = 0), rendered supersampled: each half is its own
// homography, given by the image corners of the black square's halves, for the bent-tag tests.
#include <cmath>

#include <Eigen/Dense>

#include "codes/tag_layout.hpp"
#include "detect/homography.hpp"
#include "detect/image.hpp"
#include "synthetic_tag.hpp"

namespace tagbench::synth {

struct FoldedTag {
  Corners corners;                 // TL, TR, BR, BL of the black square
  Eigen::Vector2d fold_top, fold_bottom;  // where the fold crosses the top and bottom sides
  // The halves' homographies, taking tag coordinates (u in [-1, 0] and [0, 1]).
  Eigen::Matrix3d left() const { return half({corners[0], fold_top, fold_bottom, corners[3]}, -1, 0); }
  Eigen::Matrix3d right() const { return half({fold_top, corners[1], corners[2], fold_bottom}, 0, 1); }
  static Eigen::Matrix3d half(const Corners& c, double u0, double u1) {
    Eigen::Matrix3d A;
    A << 2 / (u1 - u0), 0, -(u1 + u0) / (u1 - u0), 0, 1, 0, 0, 0, 1;
    return *tag_homography(c) * A;
  }
};

// Upright square tag of `side` px centred at (cx, cy), its fold points pushed `top` and `bottom` px
// outward (up at the top, down at the bottom): equal, as a tag folded toward the camera looks
// face-on; opposite, as the fold line seen obliquely, shifted along itself. `across` moves the fold
// line sideways (+x), as one half foreshortened more than the other.
inline FoldedTag folded_square(double cx, double cy, double side, double top, double bottom, double across = 0) {
  const double a = side / 2;
  FoldedTag t;
  t.corners = {Eigen::Vector2d(cx - a, cy - a), Eigen::Vector2d(cx + a, cy - a), Eigen::Vector2d(cx + a, cy + a),
               Eigen::Vector2d(cx - a, cy + a)};
  t.fold_top = Eigen::Vector2d(cx + across, cy - a - top);
  t.fold_bottom = Eigen::Vector2d(cx + across, cy + a + bottom);
  return t;
}

// The folded tag over a background: each image point is taken back through the half it falls in.
inline ImageF render_folded(int w, int h, const TagCells& cells, const FoldedTag& t, float background = 0.5f,
                            int ss = 6) {
  const Eigen::Matrix3d Li = t.left().inverse(), Ri = t.right().inverse();
  const auto to_tag = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
    const Eigen::Vector3d q = Li * p;
    return q.x() / q.z() <= 0 ? q : Eigen::Vector3d(Ri * p);
  };
  return render_cells(w, h, cells, to_tag, background, ss, 0.05f, 0.95f);
}

}  // namespace tagbench::synth

namespace tagbench::synth {

// The quad a line fit gives a folded_square: its bent sides' lines through their pieces' average
// (half the fold's offset), the straight sides as they are.
inline Corners fitted_quad(const FoldedTag& t) {
  Corners c = t.corners;
  const double top = 0.5 * (t.corners[0].y() - t.fold_top.y()), bottom = 0.5 * (t.fold_bottom.y() - t.corners[3].y());
  c[0].y() -= top, c[1].y() -= top, c[2].y() += bottom, c[3].y() += bottom;
  return c;
}

}  // namespace tagbench::synth
