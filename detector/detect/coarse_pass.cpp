#include "detect/coarse_pass.hpp"

#include <algorithm>

#include "detect/line_quads.hpp"  // centre_covered

namespace tagbench {

std::vector<Quad> coarse_pass_quads(const ImageF& gray, const ThresholdQuadOptions& main, std::span<const Corners> covered,
                                    const CoarsePassOptions& opt, ThresholdQuadWorkspace& ws) {
  ThresholdQuadOptions q = main;
  q.halve = true;
  q.refine_edges = false;  // refined below, only the quads no tag covers
  q.threshold.min_contrast = opt.min_contrast;
  q.threshold.low_contrast = std::min(q.threshold.low_contrast, opt.min_contrast);
  q.low_contrast.at_half_resolution = opt.low_contrast;
  q.fit.tolerate_occlusion = q.fit.tolerate_occlusion && opt.occlusion_fit;
  q.fit.min_tag_width = std::max(q.fit.min_tag_width, opt.min_tag_px);
  std::vector<Quad> quads;
  find_threshold_quads(gray, q, ws, quads);
  std::erase_if(quads, [&](const Quad& x) { return centre_covered(x, covered); });
  if (main.refine_edges) refine_threshold_quads(gray, q, quads, ws.refine);
  return quads;
}

}  // namespace tagbench
