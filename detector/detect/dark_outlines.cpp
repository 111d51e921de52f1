#include "detect/dark_outlines.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "detect/line_quads.hpp"  // centre_covered

namespace tagbench {

std::vector<Quad> dark_outline_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                                     std::span<const Corners> covered, const QuadFitOptions& fit,
                                     const EdgeRefineOptions& refine, const DarkOutlineOptions& opt,
                                     QuadFitScratch& fit_scratch, DarkOutlineScratch& s) {
  std::vector<Quad> out;
  if (!opt.enabled) return out;
  if (components.width != img.width || components.height != img.height)
    throw std::invalid_argument("dark_outline_quads: components of a " + std::to_string(components.width) + "x" +
                                std::to_string(components.height) + " image for a " + std::to_string(img.width) +
                                "x" + std::to_string(img.height) + " image");
  // Each group's dark component: the one on the dark side of its first point (the step (gx, gy)
  // points from the dark pixel to the light one).
  s.joined.points.clear();
  s.joined.offsets.assign(1, 0);
  for (const int side : {-1, 1}) {  // -1: the dark component's groups; 1: the light one's
  if (side == 1 && !opt.by_light) break;
  s.by_dark.clear();
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const BoundaryPoint& p = groups.group(g).front();
    s.by_dark.emplace_back(components.label_at((p.x2 + side * p.gx) / 2, (p.y2 + side * p.gy) / 2), static_cast<std::uint32_t>(g));
  }
  std::sort(s.by_dark.begin(), s.by_dark.end());
  for (std::size_t i = 0; i < s.by_dark.size();) {
    std::size_t j = i;
    DoubledBox box{};
    bool first = true;
    for (; j < s.by_dark.size() && s.by_dark[j].first == s.by_dark[i].first; ++j) {
      const DoubledBox b = bounding_box(groups.group(s.by_dark[j].second));
      box = first ? b : DoubledBox{std::min(box.xmin, b.xmin), std::max(box.xmax, b.xmax), std::min(box.ymin, b.ymin),
                                   std::max(box.ymax, b.ymax)};
      first = false;
    }
    const std::size_t n = j - i;
    const double side = 0.5 * std::max(box.xmax - box.xmin, box.ymax - box.ymin);
    if (s.by_dark[i].first != kNoComponent && n >= static_cast<std::size_t>(opt.min_groups) &&
        n <= static_cast<std::size_t>(opt.max_groups) && side >= opt.min_size_px && side <= opt.max_size_px) {
      for (std::size_t k = i; k < j; ++k) {
        const auto g = groups.group(s.by_dark[k].second);
        s.joined.points.insert(s.joined.points.end(), g.begin(), g.end());
      }
      s.joined.offsets.push_back(static_cast<std::uint32_t>(s.joined.points.size()));
    }
    i = j;
  }
  }
  if (s.joined.offsets.size() == 1) s.joined.offsets.clear();
  s.fitted.clear();
  QuadFitOptions f = fit;
  f.outer.ring_check = f.outer.ring_check && opt.ring_check;
  if (!opt.outline_only) {
    fit_quads(s.joined, img, f, fit_scratch, s.fitted);
  } else {
    const std::size_t min_points = static_cast<std::size_t>(std::max(f.min_points, 4));
    for (std::size_t g = 0; g < s.joined.count(); ++g) {
      const auto group = s.joined.group(g);
      outer_outline_points(group, f.outer, fit_scratch.outer, fit_scratch.side, min_points);
      std::optional<Corners> c;
      if (fit_scratch.side.size() >= min_points) {
        c = fit_quad(fit_scratch.side, img, f, fit_scratch);
        if (c && f.outer.ring_check && !outline_has_ring(*c, img, f.outer)) c.reset();
      }
      if (!c && f.outer.innermost && !fit_scratch.side.empty()) {
        const std::size_t also_outer = inner_outline_points(f.outer, fit_scratch.outer, fit_scratch.side);
        if (fit_scratch.side.size() >= 8 && static_cast<double>(also_outer) < 0.8 * static_cast<double>(fit_scratch.side.size())) {
          c = fit_quad(fit_scratch.side, img, f, fit_scratch);
          if (c && f.outer.ring_check && !outline_has_ring(*c, img, f.outer)) c.reset();
        }
      }
      if (c) s.fitted.push_back(fitted_quad(*c));
    }
  }
  for (const Quad& q : s.fitted) {
    if (centre_covered(q, covered)) continue;
    if (const auto c = refine_quad_edges(img, q.corners, refine)) {
      out.push_back(q);
      out.back().corners = *c;
    }
  }
  return out;
}

}  // namespace tagbench
