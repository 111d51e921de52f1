#include <gtest/gtest.h>

#include <cmath>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/quad_fit.hpp"
#include "detect/quad_fit_occluded.hpp"
#include "detect/threshold_quads.hpp"
#include "synthetic_occluded.hpp"

namespace test_quad_fit_occluded {

using namespace tagbench;

namespace {
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
    const ImageF img = synth::occluded_tag(truth, fraction, 200, 190);
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

}  // namespace test_quad_fit_occluded
