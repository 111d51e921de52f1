#include "detect/threshold_quads.hpp"

#include <algorithm>

#include "detect/blur.hpp"
#include "detect/noise_estimate.hpp"
#include "detect/payload_decode.hpp"  // border_contrast_plausible
#include "detect/stage_clock.hpp"

namespace tagbench {
using detail::lap_ms;
using Clock = detail::StageClock;

QuadFitOptions quad_fit_options_for(const QuadFitOptions& fit, bool halved) {
  QuadFitOptions f = fit;
  if (!halved) return f;
  f.min_tag_width = std::max(3.0, f.min_tag_width / 2);
  f.outer.max_size_px /= 2;
  if (!f.outer.at_half_resolution) f.refit_outer_outline = false;
  return f;
}

bool threshold_quads_halved(const ImageF& img, const ThresholdQuadOptions& opt) {
  return opt.halve && img.width >= 4 && img.height >= 4;
}

void refine_threshold_quads(const ImageF& img, const ThresholdQuadOptions& opt, std::span<Quad> quads,
                            EdgeRefineScratch& scratch) {
  EdgeRefineOptions r = opt.refine;
  if (threshold_quads_halved(img, opt)) r.min_range_px = std::max(r.min_range_px, 2.0);
  // The border check only where the fit is already close: a half-size pass's corners can be a pixel
  // or two off, and refining is what brings a tag's border back into the check's rings.
  const bool check = opt.refine_check.enabled && !threshold_quads_halved(img, opt);
  for (Quad& q : quads) {
    if (check &&
        !border_contrast_plausible(img, q.corners, opt.refine_check.payload_width, opt.refine_check.min_contrast))
      continue;
    if (const auto c = refine_quad_edges(img, q.corners, r, scratch)) q.corners = *c;
  }
}

void find_threshold_quads(const ImageF& img, const ThresholdQuadOptions& opt, ThresholdQuadWorkspace& ws,
                          std::vector<Quad>& out, ThresholdQuadStats* stats) {
  out.clear();
  ThresholdQuadStats st;
  auto t = Clock::now();
  const bool halve = threshold_quads_halved(img, opt);
  if (halve) half_resolution(img, ws.half);
  const ImageF& in = halve ? ws.half : img;
  st.ms_halve = lap_ms(t);
  double blur = opt.blur_sigma;
  if (blur == 0 && opt.noise_blur.enabled && !halve) {
    st.noise_grey = estimate_noise_grey(in, std::clamp((in.height - 2) / 32, 1, 16), 2);  // noise_estimate.hpp
    if (st.noise_grey >= opt.noise_blur.min_noise_grey) blur = opt.noise_blur.sigma;
  }
  st.blur_sigma = blur;
  if (blur > 0) gaussian_blur(in, blur, ws.blur_tmp, ws.blurred);
  const ImageF& th_in = blur > 0 ? ws.blurred : in;
  st.ms_blur = lap_ms(t);

  adaptive_threshold(th_in, opt.threshold, ws.pass.threshold, ws.pass.ternary);
  st.ms_threshold = lap_ms(t);
  connected_components(ws.pass.ternary, ws.pass.component_scratch, ws.pass.components, opt.dark_eight_connected);
  st.ms_components = lap_ms(t);
  group_boundaries(ws.pass.ternary, ws.pass.components, opt.boundaries, ws.pass.boundary_scratch, ws.pass.groups);
  st.ms_boundaries = lap_ms(t);

  const QuadFitOptions fit = quad_fit_options_for(opt.fit, halve);
  fit_quads(ws.pass.groups, in, fit, ws.fit, out, &ws.gave_quad);
  if (opt.low_contrast.enabled && (!halve || opt.low_contrast.at_half_resolution)) {
    auto t_low = Clock::now();
    LowContrastPassOptions low = opt.low_contrast;
    if (halve) low.max_size_px /= 2;
    low_contrast_quads(in, ws.pass.threshold, opt.threshold, opt.dark_eight_connected, opt.boundaries, fit, low, ws.low_contrast, ws.fit,
                       out);
    st.ms_low_contrast = lap_ms(t_low);
  }
  if (halve)
    for (Quad& q : out) {
      for (auto& c : q.corners) c = Eigen::Vector2d(full_from_half(c.x()), full_from_half(c.y()));
      q.observed_perimeter *= 2;
    }
  st.ms_fit = lap_ms(t);

  if (opt.refine_edges) refine_threshold_quads(img, opt, out, ws.refine);
  st.ms_refine = lap_ms(t);
  st.components = ws.pass.components.count;
  st.groups = ws.pass.groups.count();
  st.boundary_points = ws.pass.groups.points.size();
  st.quads = out.size();
  if (stats) *stats = st;
}

}  // namespace tagbench
