#include "detect/second_look.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "detect/boundaries.hpp"
#include "detect/components.hpp"
#include "detect/edge_refine.hpp"
#include "detect/homography.hpp"
#include "detect/quad_fit.hpp"
#include "detect/threshold.hpp"

namespace tagbench {

OtsuSplit otsu_split(std::span<const float> values) {
  std::array<double, 256> hist{};
  for (const float v : values) hist[static_cast<std::size_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f)] += 1;
  double n = 0, sum = 0;
  for (std::size_t i = 0; i < hist.size(); ++i) n += hist[i], sum += static_cast<double>(i) * hist[i];
  OtsuSplit best;
  if (n == 0) return best;
  double w0 = 0, s0 = 0, best_var = -1;
  for (std::size_t t = 0; t + 1 < hist.size(); ++t) {  // dark class: bins 0..t
    w0 += hist[t];
    s0 += static_cast<double>(t) * hist[t];
    const double w1 = n - w0;
    if (w0 == 0 || w1 == 0) continue;
    const double m0 = s0 / w0, m1 = (sum - s0) / w1;
    const double var = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (var > best_var) best_var = var, best = {(static_cast<double>(t) + 0.5) / 255.0, m0 / 255.0, m1 / 255.0};
  }
  if (best_var < 0) best = {sum / n / 255.0, sum / n / 255.0, sum / n / 255.0};  // one value only
  return best;
}

std::vector<Quad> second_look_quads(const ImageF& img, std::span<const Quad> quads, const std::vector<bool>& look,
                                    const ThresholdQuadOptions& tq, const SecondLookOptions& opt) {
  std::vector<Quad> out;
  ImageF roi;
  TernaryImage ternary;
  ComponentScratch cscratch;
  Components comp;
  BoundaryScratch bscratch;
  BoundaryGroups groups;
  QuadFitScratch fscratch;
  EdgeRefineScratch rscratch;
  std::vector<Quad> found;
  std::vector<float> inside;
  for (std::size_t i = 0; i < quads.size() && i < look.size(); ++i) {
    if (!look[i]) continue;
    const Corners& c = quads[i].corners;
    double x_lo = c[0].x(), x_hi = x_lo, y_lo = c[0].y(), y_hi = y_lo;
    for (const auto& p : c)
      x_lo = std::min(x_lo, p.x()), x_hi = std::max(x_hi, p.x()), y_lo = std::min(y_lo, p.y()), y_hi = std::max(y_hi, p.y());
    const double side = std::max(x_hi - x_lo, y_hi - y_lo);
    if (!(side <= opt.max_size_px) || side < opt.min_size_px) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(x_lo - opt.margin_px)));
    const int y0 = std::max(0, static_cast<int>(std::floor(y_lo - opt.margin_px)));
    const int x1 = std::min(img.width - 1, static_cast<int>(std::ceil(x_hi + opt.margin_px)));
    const int y1 = std::min(img.height - 1, static_cast<int>(std::ceil(y_hi + opt.margin_px)));
    if (x1 - x0 < 4 || y1 - y0 < 4) continue;
    roi.width = x1 - x0 + 1, roi.height = y1 - y0 + 1;  // storage reused from look to look; every pixel written below
    roi.data.resize(static_cast<std::size_t>(roi.width) * static_cast<std::size_t>(roi.height));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) roi.at(x - x0, y - y0) = img.at(x, y);
    // Otsu over the pixels inside the quad: the ink and its ring or card, less of the ground around.
    inside.clear();
    QuadRowTest in(c);  // inside_quad, bit for bit, with the sides' terms kept per quad and per row
    for (int y = y0; y <= y1; ++y) {
      in.row(y);
      for (int x = x0; x <= x1; ++x)
        if (!opt.inside_only || in.contains(x)) inside.push_back(img.at(x, y));
    }
    if (inside.size() < 16) continue;
    const OtsuSplit split = otsu_split(inside);
    if (!(split.light_mean - split.dark_mean >= opt.min_class_gap)) continue;
    ternary.width = roi.width, ternary.height = roi.height;
    ternary.data.resize(roi.data.size());
    const auto t = static_cast<float>(split.threshold);
    for (std::size_t k = 0; k < roi.data.size(); ++k) ternary.data[k] = roi.data[k] < t ? kTernaryDark : kTernaryLight;
    connected_components(ternary, cscratch, comp, tq.dark_eight_connected);
    group_boundaries(ternary, comp, tq.boundaries, bscratch, groups);
    found.clear();
    fit_quads(groups, roi, tq.fit, fscratch, found);
    for (Quad& q : found) {
      for (auto& p : q.corners) p += Eigen::Vector2d(x0, y0);
      if (tq.refine_edges)
        if (const auto r = refine_quad_edges(img, q.corners, tq.refine, rscratch)) q.corners = *r;
      double best = HUGE_VAL;  // the largest corner move against the old quad, in the best cyclic match
      for (int s = 0; s < 4; ++s) best = std::min(best, max_corner_distance(c, q.corners, s));
      if (best > opt.min_corner_change_px) out.push_back(q);
    }
  }
  return out;
}

bool wants_second_look(bool decoded, bool border_rejected, const SecondLookOptions& opt) {
  return !decoded && !(opt.skip_border_rejected && border_rejected);
}

}  // namespace tagbench
