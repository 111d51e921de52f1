#include "detect/outer_outline.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "detect/quad_fit.hpp"

namespace tagbench {

void outer_outline_points(std::span<const BoundaryPoint> group, const OuterOutlineOptions& opt,
                          OuterOutlineScratch& s, std::vector<BoundaryPoint>& out) {
  out.clear();
  one_side_points(group, true, s.side);
  if (s.side.empty()) return;
  int xmin = s.side[0].x2, xmax = xmin, ymin = s.side[0].y2, ymax = ymin;
  for (const auto& p : s.side) {
    xmin = std::min(xmin, p.x2), xmax = std::max(xmax, p.x2);
    ymin = std::min(ymin, p.y2), ymax = std::max(ymax, p.y2);
  }
  // Doubled coordinates throughout: the ratio test does not care about the scale.
  const float cx = 0.5f * static_cast<float>(xmin + xmax), cy = 0.5f * static_cast<float>(ymin + ymax);
  const int nb = std::clamp(opt.bins, 8, 1024);
  const float per_radian = static_cast<float>(nb) / (2 * std::numbers::pi_v<float>);
  const std::size_t n = s.side.size();
  s.radius.resize(n);
  s.bin.resize(n);
  s.envelope.assign(static_cast<std::size_t>(nb), 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = static_cast<float>(s.side[i].x2) - cx, dy = static_cast<float>(s.side[i].y2) - cy;
    const float a = std::atan2(dy, dx) + std::numbers::pi_v<float>;  // [0, 2 pi]
    const int b = std::min(nb - 1, static_cast<int>(a * per_radian));
    s.radius[i] = std::sqrt(dx * dx + dy * dy);
    s.bin[i] = b;
    float& e = s.envelope[static_cast<std::size_t>(b)];
    e = std::max(e, s.radius[i]);
  }
  // The envelope over each bin and its two neighbours (cyclic): a bin that holds only inner points
  // (no point of the outer edge fell into it) still sees the outer edge next to it.
  s.widened.resize(static_cast<std::size_t>(nb));
  for (int b = 0; b < nb; ++b)
    s.widened[static_cast<std::size_t>(b)] =
        std::max({s.envelope[static_cast<std::size_t>((b + nb - 1) % nb)], s.envelope[static_cast<std::size_t>(b)],
                  s.envelope[static_cast<std::size_t>((b + 1) % nb)]});
  const float keep = static_cast<float>(1 - opt.tolerance);
  for (std::size_t i = 0; i < n; ++i)
    if (s.radius[i] >= keep * s.widened[static_cast<std::size_t>(s.bin[i])]) out.push_back(s.side[i]);
}

}  // namespace tagbench
