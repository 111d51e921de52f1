#pragma once
// Supersampled renderings of tags seen through a known homography, for the detector tests.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/homography.hpp"
#include "detect/image.hpp"
#include "detect/quad_search.hpp"
#include "detect/threshold.hpp"

namespace tagbench::synth {

// Renders a tag's cells (white ring, black ring, payload) through `to_tag`, which takes an image point
// (x, y, 1) to homogeneous tag coordinates whose black square is [-1,1]^2 (z == 0: the point is at
// infinity, shown as background). Each pixel averages ss x ss sub-samples of its area (pixel centres at
// integer coordinates). Intensities: white 1, black 0 (then scaled into [black, white]).
template <class ToTag>
ImageF render_cells(int w, int h, const TagCells& cells, ToTag to_tag, float background, int ss, float black,
                    float white) {
  const double cell = 2.0 / (cells.n - 2);
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double acc = 0;
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
          const Eigen::Vector3d q = to_tag(Eigen::Vector3d(x - 0.5 + (i + 0.5) / ss, y - 0.5 + (j + 0.5) / ss, 1.0));
          if (q.z() == 0) { acc += background; continue; }
          const double tx = q.x() / q.z(), ty = q.y() / q.z();
          const int gx = static_cast<int>(std::floor((tx + 1) / cell)) + 1;
          const int gy = static_cast<int>(std::floor((ty + 1) / cell)) + 1;
          if (gx < 0 || gy < 0 || gx >= cells.n || gy >= cells.n) { acc += background; continue; }
          acc += cells.at(gy, gx) ? white : black;
        }
      img.at(x, y) = static_cast<float>(acc / (ss * ss));
    }
  return img;
}

// The tag whose black square [-1,1]^2 maps to the image through H, over a background.
inline ImageF render_tag(int w, int h, const TagCells& cells, const Eigen::Matrix3d& H, float background = 0.5f,
                         int ss = 8, float black = 0.05f, float white = 0.95f) {
  const Eigen::Matrix3d Hinv = H.inverse();
  return render_cells(
      w, h, cells, [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return Hinv * p; }, background, ss, black, white);
}

// The homography of a tag whose black square has the given image corners (TL, TR, BR, BL).
inline Eigen::Matrix3d homography_for(const Corners& c) { return *tag_homography(c); }

// Corners of an upright square of side `side` centred at (cx, cy), rotated by phi (radians, clockwise on screen),
// in the order top-left, top-right, bottom-right, bottom-left of the printed tag.
inline Corners square_tag_corners(double cx, double cy, double side, double phi) {
  const Eigen::Vector2d u(std::cos(phi), std::sin(phi)), v(-std::sin(phi), std::cos(phi));
  const Eigen::Vector2d c(cx, cy);
  const double a = side / 2;
  return {c - a * u - a * v, c + a * u - a * v, c + a * u + a * v, c - a * u + a * v};
}

// Root-mean-square distance between two sets of corners, px.
inline double corner_rms(const Corners& a, const Corners& b) {
  double s = 0;
  for (std::size_t i = 0; i < 4; ++i) s += (a[i] - b[i]).squaredNorm();
  return std::sqrt(s / 4);
}

// The corners each moved by up to `amount` px in x and y (uniform, seeded).
inline Corners perturbed(const Corners& c, double amount, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  Corners p = c;
  for (auto& q : p) q += Eigen::Vector2d(u(rng), u(rng));
  return p;
}

// The convex quad `c` filled with `inside` on `outside` (size x size px), each pixel the mean of
// 4 x 4 samples, then blurred by 0.8 px like a camera's optics.
inline ImageF filled_quad_image(int size, const Corners& c, float outside, float inside) {
  ImageF img(size, size, outside);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      int hits = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) hits += inside_quad(c, {x - 0.375 + 0.25 * sx, y - 0.375 + 0.25 * sy});
      img.at(x, y) = outside + (inside - outside) * static_cast<float>(hits) / 16.0f;
    }
  return gaussian_blur(img, 0.8);
}

// The smallest worst-corner distance between `want` and any of `quads` (any starting corner), px.
inline double best_quad_match(const std::vector<Quad>& quads, const Corners& want) {
  double best = 1e9;
  for (const Quad& q : quads)
    for (int r = 0; r < 4; ++r) {
      double worst = 0;
      for (int i = 0; i < 4; ++i) worst = std::max(worst, (q.corners[(i + r) % 4] - want[i]).norm());
      best = std::min(best, worst);
    }
  return best;
}

// The threshold stage's first three steps on `img` at their defaults (dark 8-connected): the classes,
// the components and the boundary groups, for tests of what is fitted to them.
struct ThresholdPass {
  ThresholdScratch th;
  TernaryImage ternary;
  ComponentScratch cs;
  Components comp;
  BoundaryScratch bs;
  BoundaryGroups groups;
  explicit ThresholdPass(const ImageF& img) {
    adaptive_threshold(img, ThresholdOptions{}, th, ternary);
    connected_components(ternary, cs, comp, true);
    group_boundaries(ternary, comp, BoundaryOptions{}, bs, groups);
  }
};

}  // namespace tagbench::synth
