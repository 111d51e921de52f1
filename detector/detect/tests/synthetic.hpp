#pragma once
// Synthetic test images for the detect/ tests (pixel centres at integer coordinates, y down).
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "detect/image.hpp"

namespace tagbench::synth {

// A convex polygon (vertices in either order) rendered by ss x ss supersampling of every pixel
// [x - 0.5, x + 0.5] x [y - 0.5, y + 0.5]: the area-weighted mix of inside and outside.
inline ImageF render_convex_polygon(int w, int h, const std::vector<Eigen::Vector2d>& poly, float inside,
                                    float outside, int ss = 16) {
  double orient = 0.0;  // sign of the polygon's signed area, to accept either vertex order
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    orient += a.x() * b.y() - b.x() * a.y();
  }
  auto is_inside = [&](double x, double y) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      const double c = (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
      if (c * orient < 0) return false;
    }
    return true;
  };
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int in = 0;
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) in += is_inside(x - 0.5 + (i + 0.5) / ss, y - 0.5 + (j + 0.5) / ss);
      const float f = static_cast<float>(in) / static_cast<float>(ss * ss);
      img.at(x, y) = f * inside + (1.0f - f) * outside;
    }
  return img;
}

// Corners of a square with centre c, half side a, rotated by angle phi, listed so that the walk
// corner[k] -> corner[k+1] is counter-clockwise ON SCREEN (y down), i.e. the interior is on the
// left: that is the order in which "dark on the left" segments of a dark square must run.
inline std::array<Eigen::Vector2d, 4> square_corners_ccw(Eigen::Vector2d c, double a, double phi) {
  const Eigen::Vector2d u(std::cos(phi), std::sin(phi)), v(-std::sin(phi), std::cos(phi));
  // With y down, u = +x and v = +y: the screen-CCW order is top-right, top-left, bottom-left, bottom-right.
  return {c + a * (u - v), c + a * (-u - v), c + a * (-u + v), c + a * (u + v)};
}

inline void add_gaussian_noise(ImageF& img, double stddev, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, static_cast<float>(stddev));
  for (float& v : img.data) v += n(rng);
}

}  // namespace tagbench::synth
