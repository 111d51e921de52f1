#include "detect/find_quads_in_image.hpp"

#include <algorithm>


#include "detect/blur.hpp"
#include "detect/stage_clock.hpp"
#include "detect/gradient.hpp"
#include "detect/segmentation.hpp"
#include "detect/workspace_impl.hpp"

namespace tagbench {
using detail::lap_ms;
using Clock = detail::StageClock;

FoundQuads find_quads_in_image(const ImageF& gray, const DetectorOptions& opt, DetectorWorkspace& workspace,
                               StageTimings* timings, DetectorTrace* trace) {
  DetectorWorkspace::Impl& ws = workspace.impl();
  StageTimings tm;
  auto t = Clock::now();
  FoundQuads out;

  // 1. Blur (and halve) for segmentation; the decoding image is separate.
  const bool halve = opt.half_resolution && gray.width >= 4 && gray.height >= 4;
  if (halve)
    blur_and_halve(gray, opt.seg_sigma, ws.blur_tmp, ws.seg_in);
  else
    gaussian_blur(gray, opt.seg_sigma, ws.blur_tmp, ws.seg_in);
  if (opt.decode_sigma > 0) gaussian_blur(gray, opt.decode_sigma, ws.blur_tmp, ws.dec_in);
  out.decode_image = opt.decode_sigma > 0 ? &ws.dec_in : &gray;
  tm.blur = lap_ms(t);

  // 2. Gradients; 3. clusters; 4. segments.
  compute_gradients(ws.seg_in, opt.segmentation.min_mag, ws.gradients);
  tm.gradient = lap_ms(t);
  segment_clusters(ws.gradients, opt.segmentation, ws.seg, ws.clusters);
  tm.segmentation = lap_ms(t);
  out.segments = fit_segments(ws.clusters, opt.line_fit);
  if (halve)
    for (auto& s : out.segments) s = segment_full_from_half(s);
  tm.line_fit = lap_ms(t);

  // 5. Quads.
  out.quads = find_quads(out.segments, opt.quad_search);
  tm.quads = lap_ms(t);

  if (timings) {
    timings->blur = tm.blur;
    timings->gradient = tm.gradient;
    timings->segmentation = tm.segmentation;
    timings->line_fit = tm.line_fit;
    timings->quads = tm.quads;
    timings->segment_count = out.segments.size();
    timings->quad_count = out.quads.size();
  }
  if (trace) {
    const Gradients& g = ws.gradients;
    trace->segmentation_input = ws.seg_in;
    trace->segmentation_scale = static_cast<double>(gray.width) / std::max(1, ws.seg_in.width);
    trace->gradient_magnitude = ImageF(g.width, g.height);
    trace->gradient_direction = ImageF(g.width, g.height);
    trace->gradient_magnitude.data.assign(g.mag.begin(), g.mag.end());
    trace->gradient_direction.data.assign(g.theta.begin(), g.theta.end());
    trace->clusters = ws.clusters;  // copies: the workspace keeps its buffers
    trace->segments = out.segments;
    trace->quads = out.quads;
  }
  return out;
}

}  // namespace tagbench
