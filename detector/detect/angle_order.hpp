#pragma once
// Ordering boundary points by their angle around a centre (quad_fit.hpp, quad_fit_occluded.hpp): both
// fits walk a group's outline once by sorting its points on a pseudo-angle. The sort was about a
// tenth of the default profile's time on the realistic set (std::sort of ~100 points, most
// comparisons mispredicted); here it is a counting pass and an insertion sort within buckets.
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

namespace tagbench {

// Monotone in atan2(dy, dx) over [0, 2 pi), values in [0, 4) and never -0: cheaper than atan2 and all
// a sort needs.
inline float pseudo_angle(float dx, float dy) {
  const float s = std::abs(dx) + std::abs(dy);
  if (s == 0) return 0;
  if (dy >= 0) return (dx >= 0 ? dy / s : 1 - dx / s) + 0.0f;  // dy / s may be -0 when dy is
  return dx < 0 ? 2 - dy / s : 3 + dx / s;
}

// A pseudo-angle and an index packed into one integer that orders as (key, index): the bits of a
// float >= 0 order as its values do.
inline std::uint64_t angle_key(float pseudo_angle, std::uint32_t index) {
  return std::uint64_t{std::bit_cast<std::uint32_t>(pseudo_angle)} << 32 | index;
}
inline std::uint32_t index_of(std::uint64_t key) { return static_cast<std::uint32_t>(key); }

struct AngleSortScratch {
  std::vector<std::uint64_t> placed;
  std::vector<std::uint32_t> buckets;
};

// `keys` (angle_key values) sorted ascending: the order std::sort gives, since packed keys with
// distinct indices are distinct. Linear for keys spread around a closed outline: a counting pass into
// about one bucket per key by its angle, then an insertion sort that moves keys only within a bucket.
void sort_angle_keys(std::vector<std::uint64_t>& keys, AngleSortScratch& scratch);

}  // namespace tagbench
