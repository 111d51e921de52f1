#include "detect/find_threshold_quads_in_image.hpp"

#include "detect/blur.hpp"
#include "detect/threshold_quads.hpp"
#include "detect/workspace_impl.hpp"

namespace tagbench {

FoundQuads find_threshold_quads_in_image(const ImageF& gray, const DetectorOptions& opt, DetectorWorkspace& workspace,
                                         StageTimings* timings, DetectorTrace* trace) {
  DetectorWorkspace::Impl& ws = workspace.impl();
  FoundQuads out;
  ThresholdQuadOptions q = opt.threshold_quads;
  q.halve = opt.half_resolution;
  ThresholdQuadStats st;
  find_threshold_quads(gray, q, ws.threshold_quads, out.quads, &st);
  if (opt.decode_sigma > 0) gaussian_blur(gray, opt.decode_sigma, ws.blur_tmp, ws.dec_in);
  out.decode_image = opt.decode_sigma > 0 ? &ws.dec_in : &gray;
  if (timings) {
    timings->blur = st.ms_halve + st.ms_blur;
    timings->gradient = 0;
    timings->segmentation = st.ms_threshold + st.ms_components;
    timings->quads = st.ms_boundaries + st.ms_fit;
    timings->line_fit = st.ms_refine;
    timings->segment_count = 0;
    timings->quad_count = out.quads.size();
  }
  if (trace) {
    const bool halved = q.halve && !ws.threshold_quads.half.empty();
    trace->segmentation_input = halved ? ws.threshold_quads.half : gray;
    trace->segmentation_scale = halved ? static_cast<double>(gray.width) / ws.threshold_quads.half.width : 1.0;
    trace->quads = out.quads;
    trace->threshold_classes = ws.threshold_quads.pass.ternary;
    trace->boundary_groups = ws.threshold_quads.pass.groups;
  }
  return out;
}

}  // namespace tagbench
