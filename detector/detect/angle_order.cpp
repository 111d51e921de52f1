#include "detect/angle_order.hpp"

#include <algorithm>

namespace tagbench {

void sort_angle_keys(std::vector<std::uint64_t>& keys, AngleSortScratch& s) {
  const std::size_t n = keys.size();
  if (n < 2) return;
  const std::uint32_t nb = std::bit_ceil(static_cast<std::uint32_t>(n));
  const float per_unit = 0.25f * static_cast<float>(nb);  // the keys lie in [0, 4)
  auto bucket = [&](std::uint64_t k) {  // monotone in the key, so buckets keep the keys' order
    const float angle = std::bit_cast<float>(static_cast<std::uint32_t>(k >> 32));
    return std::min(nb - 1, static_cast<std::uint32_t>(angle * per_unit));
  };
  s.buckets.assign(static_cast<std::size_t>(nb) + 1, 0);
  for (const std::uint64_t k : keys) ++s.buckets[bucket(k) + 1];
  for (std::uint32_t b = 0; b < nb; ++b) s.buckets[b + 1] += s.buckets[b];
  s.placed.resize(n);
  for (const std::uint64_t k : keys) s.placed[s.buckets[bucket(k)]++] = k;
  for (std::size_t i = 1; i < n; ++i) {  // only keys of one bucket are out of order
    const std::uint64_t k = s.placed[i];
    std::size_t j = i;
    for (; j > 0 && s.placed[j - 1] > k; --j) s.placed[j] = s.placed[j - 1];
    s.placed[j] = k;
  }
  keys.swap(s.placed);
}

}  // namespace tagbench
