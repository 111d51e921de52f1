#pragma once
// Test scenes of the second look and the group look (test_second_look.cpp, test_group_look.cpp): a
// dark square on a lighter card on a ground, a square quad, and the corner error up to a cyclic shift.
#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "detect/homography.hpp"
#include "detect/image.hpp"
#include "detect/quad_search.hpp"

namespace tagbench::test_scenes {

// A dark ground, a lighter card, on it a dark square of pixels [s0, s0 + n) on both axes (edges at
// s0 - 0.5 and s0 + n - 0.5; pixel centres at integers).
inline ImageF card_scene(float ground, float card, float ink, int card0, int card_n, int s0, int n) {
  ImageF img(80, 80, ground);
  for (int y = card0; y < card0 + card_n; ++y)
    for (int x = card0; x < card0 + card_n; ++x) img.at(x, y) = card;
  for (int y = s0; y < s0 + n; ++y)
    for (int x = s0; x < s0 + n; ++x) img.at(x, y) = ink;
  return img;
}

// The axis-aligned quad [lo, hi]^2, corners clockwise on screen from the top-left.
inline Quad square_quad(double lo, double hi) {
  Quad q;
  q.corners = {Eigen::Vector2d(lo, lo), Eigen::Vector2d(hi, lo), Eigen::Vector2d(hi, hi), Eigen::Vector2d(lo, hi)};
  return q;
}

// The largest corner distance between `found` and `want` under the best cyclic shift of the corners.
inline double worst_corner_error(const Corners& found, const Corners& want) {
  double best = HUGE_VAL;
  for (int s = 0; s < 4; ++s) best = std::min(best, max_corner_distance(want, found, s));
  return best;
}

}  // namespace tagbench::test_scenes
