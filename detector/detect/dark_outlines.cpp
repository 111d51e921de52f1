#include "detect/dark_outlines.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "detect/line_quads.hpp"  // centre_covered
#include "detect/payload_decode.hpp"  // border_worth_refining

namespace tagbench {

std::vector<Quad> dark_outline_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                                     std::span<const Corners> covered, const QuadFitOptions& fit,
                                     const EdgeRefineOptions& refine, const DarkOutlineOptions& opt,
                                     QuadFitScratch& fit_scratch, DarkOutlineScratch& s,
                                     const ThresholdQuadOptions::RefineCheck& check) {
  std::vector<Quad> out;
  if (!opt.enabled) return out;
  if (components.width != img.width || components.height != img.height)
    throw std::invalid_argument("dark_outline_quads: components of a " + std::to_string(components.width) + "x" +
                                std::to_string(components.height) + " image for a " + std::to_string(img.width) +
                                "x" + std::to_string(img.height) + " image");
  s.joined.points.clear();
  s.joined.offsets.assign(1, 0);
  // Joins the groups that share the component on one side of their first point (-1: the dark side,
  // as the step (gx, gy) points from the dark pixel to the light one; 1: the light side).
  const auto join_by = [&](int side) {
    s.by_component.clear();
    for (std::size_t g = 0; g < groups.count(); ++g) {
      const BoundaryPoint& p = groups.group(g).front();
      s.by_component.emplace_back(components.label_at((p.x2 + side * p.gx) / 2, (p.y2 + side * p.gy) / 2),
                                  static_cast<std::uint32_t>(g));
    }
    std::sort(s.by_component.begin(), s.by_component.end());
    for (std::size_t i = 0, j = 0; i < s.by_component.size(); i = j) {
      DoubledBox box = bounding_box(groups.group(s.by_component[i].second));
      for (j = i + 1; j < s.by_component.size() && s.by_component[j].first == s.by_component[i].first; ++j) {
        const DoubledBox b = bounding_box(groups.group(s.by_component[j].second));
        box = {std::min(box.xmin, b.xmin), std::max(box.xmax, b.xmax), std::min(box.ymin, b.ymin),
               std::max(box.ymax, b.ymax)};
      }
      const std::size_t n = j - i;
      const double size = 0.5 * std::max(box.xmax - box.xmin, box.ymax - box.ymin);
      if (s.by_component[i].first == kNoComponent || n < static_cast<std::size_t>(opt.min_groups) ||
          n > static_cast<std::size_t>(opt.max_groups) || size < opt.min_size_px || size > opt.max_size_px)
        continue;
      for (std::size_t k = i; k < j; ++k) {
        const auto g = groups.group(s.by_component[k].second);
        s.joined.points.insert(s.joined.points.end(), g.begin(), g.end());
      }
      s.joined.offsets.push_back(static_cast<std::uint32_t>(s.joined.points.size()));
    }
  };
  join_by(-1);
  if (opt.by_light) join_by(1);
  if (s.joined.offsets.size() == 1) s.joined.offsets.clear();
  s.fitted.clear();
  QuadFitOptions f = fit;
  f.outer.ring_check = f.outer.ring_check && opt.ring_check;
  if (!opt.outline_only) {
    fit_quads(s.joined, img, f, fit_scratch, s.fitted);
  } else {
    for (std::size_t g = 0; g < s.joined.count(); ++g) {
      outer_outline_points(s.joined.group(g), f.outer, fit_scratch.outer, fit_scratch.side,
                           static_cast<std::size_t>(std::max(f.min_points, 4)));
      auto c = fit_outline(fit_scratch.side, img, f, fit_scratch);
      if (!c && f.outer.innermost) c = fit_innermost_outline(img, f, fit_scratch);
      if (c) s.fitted.push_back(fitted_quad(*c));
    }
  }
  for (const Quad& q : s.fitted) {
    if (centre_covered(q, covered)) continue;
    // Refused by the pre-filter: left as fitted, for the decoder's pre-filter to refuse by the same
    // test (the quad stays in the trace, where --explain finds it), as the threshold quads' refine_check.
    if (opt.check_before_refining && check.enabled &&
        !border_worth_refining(img, q.corners, check.payload_width, check.min_contrast, opt.slack_sides)) {
      out.push_back(q);
      continue;
    }
    if (const auto c = refine_quad_edges(img, q.corners, refine, s.refine)) {
      out.push_back(q);
      out.back().corners = *c;
    }
  }
  return out;
}

}  // namespace tagbench
