#pragma once
// A tag with an occluder over part of one border edge, as tagbench raytrace conditions renders it.
#include <cmath>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "synthetic_tag.hpp"

namespace tagbench::synth {

// A 36h11 tag whose bottom border edge is covered over its middle `fraction` by a grey (0.35) patch
// from half into the black ring to half a cell beyond the white ring: the ray-traced occlusion
// condition of tagbench raytrace conditions.
inline ImageF occluded_tag(const Corners& truth, double fraction, int w, int h) {
  const TagFamily& f = builtin_family("36h11");
  ImageF img = synth::render_tag(w, h, tag_cells(f, 7), synth::homography_for(truth), 0.5f, 6);
  const Eigen::Matrix3d H = synth::homography_for(truth);
  const Eigen::Matrix3d Hinv = H.inverse();
  const double cell = 2.0 / 8;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double acc = 0;
      const int ss = 6;
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
          const Eigen::Vector3d q = Hinv * Eigen::Vector3d(x - 0.5 + (i + 0.5) / ss, y - 0.5 + (j + 0.5) / ss, 1.0);
          const double tx = q.x() / q.z(), ty = q.y() / q.z();
          acc += std::abs(tx) < fraction && ty > 1 - 0.5 * cell && ty < 1 + 1.5 * cell;
        }
      const float a = static_cast<float>(acc / (ss * ss));
      img.at(x, y) = a * 0.35f + (1 - a) * img.at(x, y);
    }
  return img;
}

}  // namespace tagbench::synth
