#include "detect/ring_quads.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tagbench {

std::vector<Quad> ring_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                             const QuadFitOptions& fit, const RingQuadOptions& opt, QuadFitScratch& scratch) {
  std::vector<Quad> out;
  if (!opt.enabled) return out;
  if (components.width != img.width || components.height != img.height)
    throw std::invalid_argument("ring_quads: components of a " + std::to_string(components.width) + "x" +
                                std::to_string(components.height) + " image for a " + std::to_string(img.width) + "x" +
                                std::to_string(img.height) + " image");
  // Each group's light component: the one on the light side of its first point (doubled coordinates;
  // the step (gx, gy) points from the dark pixel to the light one).
  std::vector<std::uint32_t> light_of(groups.count(), kNoComponent);
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const BoundaryPoint& p = groups.group(g).front();
    light_of[g] = components.label_at((p.x2 + p.gx) / 2, (p.y2 + p.gy) / 2);
  }
  QuadFitOptions light = fit;
  light.dark_inside = false;
  light.light_inside = true;
  const std::size_t min_points = static_cast<std::size_t>(std::max(fit.min_points, 4));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> by_light;  // (light id, group)
  if (opt.min_hole > 0) {
    for (std::size_t g = 0; g < groups.count(); ++g) by_light.emplace_back(light_of[g], static_cast<std::uint32_t>(g));
    std::sort(by_light.begin(), by_light.end());
  }
  for (std::size_t g = 0; g < groups.count(); ++g) {
    const auto group = groups.group(g);
    if (group.size() < min_points) continue;
    const auto [xmin, xmax, ymin, ymax] = bounding_box(group);  // doubled pixels
    const double w = 0.5 * (xmax - xmin), h = 0.5 * (ymax - ymin), side = std::max(w, h);
    if (side < opt.min_size_px || side > opt.max_size_px) continue;
    const double light_pixels = light_of[g] == kNoComponent ? 0.0 : static_cast<double>(components.size[light_of[g]]);
    if (light_pixels > opt.max_fill * w * h) continue;
    if (opt.min_hole > 0) {
      bool hole = false;
      auto it = std::lower_bound(by_light.begin(), by_light.end(), std::make_pair(light_of[g], std::uint32_t{0}));
      for (; !hole && it != by_light.end() && it->first == light_of[g]; ++it) {
        if (it->second == g) continue;
        const auto b = bounding_box(groups.group(it->second));
        hole = b.xmin > xmin && b.xmax < xmax && b.ymin > ymin && b.ymax < ymax &&
               (b.xmax - b.xmin) >= opt.min_hole * (xmax - xmin) && (b.ymax - b.ymin) >= opt.min_hole * (ymax - ymin);
      }
      if (!hole) continue;
    }
    if (const auto c = fit_quad(group, img, light, scratch)) out.push_back(fitted_quad(*c));
  }
  return out;
}

}  // namespace tagbench
