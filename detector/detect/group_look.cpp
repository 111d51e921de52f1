#include "detect/group_look.hpp"

#include <algorithm>
#include <cmath>

namespace tagbench {

namespace {

struct Box {
  double x0, y0, x1, y1;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

Box box_of(const Corners& c) {
  Box b{c[0].x(), c[0].y(), c[0].x(), c[0].y()};
  for (const auto& p : c) b.x0 = std::min(b.x0, p.x()), b.y0 = std::min(b.y0, p.y()), b.x1 = std::max(b.x1, p.x()), b.y1 = std::max(b.y1, p.y());
  return b;
}

}  // namespace

std::vector<Quad> group_look_windows(const BoundaryGroups& groups, std::span<const Quad> found, int width, int height,
                                     const GroupLookOptions& opt) {
  std::vector<Quad> out;
  if (!opt.enabled || width < 1 || height < 1) return out;
  std::vector<Box> covered;  // the found quads' boxes (a quad's box holds its outline's groups' centres)
  covered.reserve(found.size());
  for (const Quad& q : found) covered.push_back(box_of(q.corners));
  std::vector<Box> windows;
  for (std::size_t g = 0; g < groups.count() && static_cast<int>(windows.size()) < opt.max_windows; ++g) {
    const auto pts = groups.group(g);
    if (static_cast<int>(pts.size()) < opt.min_points) continue;
    const DoubledBox b = bounding_box(pts);
    const double side = 0.5 * std::max(b.xmax - b.xmin, b.ymax - b.ymin);
    if (side < opt.min_size_px || side > opt.max_size_px) continue;
    const double cx = 0.25 * (b.xmin + b.xmax), cy = 0.25 * (b.ymin + b.ymax);
    // A group inside a found quad's box was fitted (or is that quad's payload): the quad and the second
    // look have seen it. A quad's box is tight, so a ring piece just outside a wrong quad still counts.
    bool seen = false;
    for (const Box& c : covered) seen = seen || c.contains(cx, cy);
    for (const Box& w : windows) seen = seen || w.contains(cx, cy);
    if (seen) continue;
    const double half = 0.5 * std::max(opt.min_window_px, side + 2 * opt.margin_px);
    const Box w{std::max(0.0, std::floor(cx - half)), std::max(0.0, std::floor(cy - half)),
                std::min(width - 1.0, std::ceil(cx + half)), std::min(height - 1.0, std::ceil(cy + half))};
    if (w.x1 - w.x0 < 4 || w.y1 - w.y0 < 4) continue;
    windows.push_back(w);
    Quad q;
    q.corners = {Eigen::Vector2d(w.x0, w.y0), Eigen::Vector2d(w.x1, w.y0), Eigen::Vector2d(w.x1, w.y1), Eigen::Vector2d(w.x0, w.y1)};
    q.segments = {-1, -1, -1, -1};
    out.push_back(q);
  }
  return out;
}

std::vector<Quad> group_look_quads(const ImageF& gray, const BoundaryGroups& groups, std::span<const Quad> quads,
                                   const std::vector<bool>& looked, std::span<const Quad> again,
                                   const ThresholdQuadOptions& threshold, const SecondLookOptions& second,
                                   const GroupLookOptions& opt) {
  std::vector<Quad> covered;
  for (std::size_t i = 0; i < quads.size(); ++i) {
    const Box b = box_of(quads[i].corners);
    if (!looked[i] || std::max(b.x1 - b.x0, b.y1 - b.y0) <= second.max_size_px) covered.push_back(quads[i]);
  }
  covered.insert(covered.end(), again.begin(), again.end());
  const std::vector<Quad> windows = group_look_windows(groups, covered, gray.width, gray.height, opt);
  SecondLookOptions whole = second;  // a window is looked at whole, whatever its size
  whole.max_size_px = HUGE_VAL, whole.margin_px = 0, whole.inside_only = false;
  return second_look_quads(gray, windows, std::vector<bool>(windows.size(), true), threshold, whole);
}

}  // namespace tagbench
