#include "detect/suppress_duplicates.hpp"

#include <algorithm>
#include <numeric>

#include "detect/homography.hpp"  // inside_quad

namespace tagbench {

std::vector<Detection> suppress_overlaps(std::vector<Detection> found, double max_perimeter_ratio) {
  // Best reading first (fewer bits corrected, then the higher margin, then input order); each is kept
  // when it overlaps no reading kept before it; the kept ones are returned in input order. So the
  // result does not depend on the input order but through full ties, and no two kept ones overlap.
  std::vector<std::size_t> rank(found.size());
  std::iota(rank.begin(), rank.end(), std::size_t{0});
  std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
    const Detection &x = found[a], &y = found[b];
    return x.hamming < y.hamming || (x.hamming == y.hamming && x.decision_margin > y.decision_margin);
  });
  const auto overlap = [&](const Detection& a, const Detection& b) {
    if (a.family == b.family && a.id == b.id) return false;  // suppress_duplicates' case
    const double pa = perimeter(a.corners), pb = perimeter(b.corners);
    if (!(std::max(pa, pb) < max_perimeter_ratio * std::min(pa, pb))) return false;  // NaN: false
    return inside_quad(a.corners, b.center) && inside_quad(b.corners, a.center);
  };
  std::vector<std::size_t> kept;
  for (const std::size_t i : rank)
    if (std::none_of(kept.begin(), kept.end(), [&](std::size_t j) { return overlap(found[i], found[j]); }))
      kept.push_back(i);
  std::sort(kept.begin(), kept.end());  // input order
  std::vector<Detection> out;
  for (const std::size_t i : kept) out.push_back(std::move(found[i]));
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
