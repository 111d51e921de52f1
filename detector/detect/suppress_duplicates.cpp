#include "detect/suppress_duplicates.hpp"

namespace tagbench {
namespace {

double perimeter(const Corners& c) {
  double p = 0;
  for (int i = 0; i < 4; ++i) p += (c[static_cast<std::size_t>((i + 1) % 4)] - c[static_cast<std::size_t>(i)]).norm();
  return p;
}

}  // namespace

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
