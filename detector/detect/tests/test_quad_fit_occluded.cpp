#include <gtest/gtest.h>

#include <cmath>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/quad_fit.hpp"
#include "detect/quad_fit_occluded.hpp"
#include "detect/threshold_quads.hpp"
#include "synthetic_tag.hpp"

using namespace tagbench;

namespace {
// A 36h11 tag whose bottom border edge is covered over its middle `fraction` by a grey (0.35) patch
// from half into the black ring to half a cell beyond the white ring: the ray-traced occlusion
// condition of tagbench raytrace conditions.
ImageF occluded_tag(const Corners& truth, double fraction, int w, int h) {
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

double max_corner_error(const Corners& found, const Corners& truth) {  // found clockwise, any start
  double best = HUGE_VAL;
  for (std::size_t k = 0; k < 4; ++k) {
    double e = 0;
    for (std::size_t i = 0; i < 4; ++i) e = std::max(e, (found[(k + i) % 4] - truth[i]).norm());
    best = std::min(best, e);
  }
  return best;
}
}  // namespace

TEST(QuadFitOccluded, OccludedTagGivesItsSquareNotTheOccluder) {
  for (double fraction : {0.2, 0.4, 0.6, 0.8}) {
    const Corners truth = synth::square_tag_corners(100.3, 95.6, 64, 0.45);
    const ImageF img = occluded_tag(truth, fraction, 200, 190);
    ThresholdQuadOptions opt;
    opt.refine_edges = false;
    ThresholdQuadWorkspace ws;
    std::vector<Quad> quads;
    find_threshold_quads(img, opt, ws, quads);
    bool found_plain = false;
    for (const Quad& q : quads) found_plain |= max_corner_error(q.corners, truth) < 1.0;
    EXPECT_FALSE(found_plain) << "fit_quad alone does not find the occluded square (else this test shows nothing)";
    opt.fit.tolerate_occlusion = true;
    find_threshold_quads(img, opt, ws, quads);
    double best = HUGE_VAL;
    for (const Quad& q : quads) best = std::min(best, max_corner_error(q.corners, truth));
    EXPECT_LT(best, 0.5) << "fraction " << fraction;
  }
}
