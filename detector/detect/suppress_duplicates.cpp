#include "detect/suppress_duplicates.hpp"

#include <algorithm>

namespace tagbench {
namespace {

double perimeter(const Corners& c) {
  double p = 0;
  for (int i = 0; i < 4; ++i) p += (c[static_cast<std::size_t>((i + 1) % 4)] - c[static_cast<std::size_t>(i)]).norm();
  return p;
}

// Whether p lies inside the convex quad c (either winding; on an edge counts as inside).
bool inside(const Corners& c, const Eigen::Vector2d& p) {
  int pos = 0, neg = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d e = c[(i + 1) % 4] - c[i], q = p - c[i];
    const double z = e.x() * q.y() - e.y() * q.x();
    pos += z > 0;
    neg += z < 0;
  }
  return pos == 0 || neg == 0;
}

}  // namespace

std::vector<Detection> suppress_overlaps(std::vector<Detection> found, double max_perimeter_ratio) {
  std::vector<Detection> out;
  for (auto& d : found) {
    bool replaced = false, dropped = false;
    const double pd = perimeter(d.corners);
    for (auto& o : out) {
      if (o.family == d.family && o.id == d.id) continue;  // suppress_duplicates' case
      const double po = perimeter(o.corners);
      if (!(std::max(pd, po) < max_perimeter_ratio * std::min(pd, po))) continue;
      if (!inside(o.corners, d.center) || !inside(d.corners, o.center)) continue;
      const bool better = d.hamming < o.hamming || (d.hamming == o.hamming && d.decision_margin > o.decision_margin);
      if (better) {
        o = std::move(d);
        replaced = true;
      } else {
        dropped = true;
      }
      break;
    }
    if (!replaced && !dropped) out.push_back(std::move(d));
  }
  return out;
}

std::vector<Detection> suppress_duplicates(std::vector<Detection> found) {
  std::vector<Detection> out;
  for (auto& d : found) {
    bool replaced = false, dropped = false;
    for (auto& o : out) {
      if (o.family != d.family || o.id != d.id) continue;
      if ((o.center - d.center).norm() >= (perimeter(o.corners) + perimeter(d.corners)) / 16) continue;
      const bool better = d.hamming < o.hamming || (d.hamming == o.hamming && d.observed_perimeter > o.observed_perimeter);
      if (better && !replaced) {
        o = d;
        replaced = true;
      } else {
        dropped = true;
      }
      break;
    }
    if (!replaced && !dropped) out.push_back(std::move(d));
  }
  return out;
}

void drop_below_margin(std::vector<Detection>& detections, double min_decision_margin) {
  std::erase_if(detections, [&](const Detection& d) { return d.decision_margin < min_decision_margin; });
}

}  // namespace tagbench
