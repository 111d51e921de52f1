#include "detect/soft_decode.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>


namespace tagbench {

SoftMatch soft_match(const TagFamily& family, std::span<const float> z, const SoftDecodeOptions& opt) {
  SoftMatch m;
  const int n = family.bits();
  if (n < 1 || static_cast<int>(z.size()) != n) return m;
  // Per bit (bit index b = n-1-k): the hard bit and its weight; the ascending weights' prefix sums
  // bound from below the distance of any word p hard bits away.
  std::array<double, 64> weight{};
  std::array<double, 65> prefix{};
  double scale = 0;  // mean |z|
  for (const float v : z) scale += std::abs(v);
  scale /= n;
  if (!(scale > 0) || !std::isfinite(scale)) return m;
  Code hard = 0;
  for (int k = 0; k < n; ++k) {
    const double v = z[static_cast<std::size_t>(k)];
    const int b = n - 1 - k;
    weight[static_cast<std::size_t>(b)] = std::min(std::abs(v) / scale, opt.confidence_cap);
    if (v > 0) hard |= Code{1} << b;
  }
  std::array<double, 64> sorted = weight;
  std::sort(sorted.begin(), sorted.begin() + n);
  for (int p = 0; p < n; ++p) prefix[static_cast<std::size_t>(p + 1)] = prefix[static_cast<std::size_t>(p)] + sorted[static_cast<std::size_t>(p)];
  constexpr double kInf = std::numeric_limits<double>::infinity();
  m.best_distance = m.second_distance = kInf;
  const auto words = family.rotated_words();
  for (std::size_t i = 0; i < words.size(); ++i) {
    Code diff = words[i] ^ hard;
    const int p = std::popcount(diff);
    if (prefix[static_cast<std::size_t>(p)] >= m.second_distance) continue;  // cannot beat the runner-up
    double dist = 0;
    while (diff) {
      dist += weight[static_cast<std::size_t>(std::countr_zero(diff))];
      diff &= diff - 1;
    }
    if (dist < m.best_distance) {
      m.second = m.best, m.second_distance = m.best_distance, m.second_bit_errors = m.best_bit_errors;
      m.best = static_cast<int>(i), m.best_distance = dist, m.best_bit_errors = p;
    } else if (dist < m.second_distance) {
      m.second = static_cast<int>(i), m.second_distance = dist, m.second_bit_errors = p;
    }
  }
  return m;
}

double quad_area_ratio(const Corners& corners) {
  const double mean_side = perimeter(corners) / 4;
  return mean_side > 0 ? std::abs(twice_signed_area(corners)) / 2 / (mean_side * mean_side) : 0.0;
}

double quad_opposite_ratio(const Corners& corners) {
  double worst = 1;
  for (int k = 0; k < 2; ++k) {
    const double a = (corners[k + 1] - corners[k]).norm(), b = (corners[(k + 3) % 4] - corners[k + 2]).norm();
    worst = std::min(worst, std::max(a, b) > 0 ? std::min(a, b) / std::max(a, b) : 0.0);
  }
  return worst;
}

std::optional<DecodeResult> soft_decode(const TagFamily& family, const PayloadReading& reading,
                                        const SoftDecodeOptions& opt) {
  if (family.min_hamming() < opt.min_family_hamming || static_cast<int>(reading.confidence.size()) != family.bits())
    return std::nullopt;
  // Cheap first: the best codeword must lie within max_bit_errors hard bits, so a reading with no word
  // that near (most refused quads: a random word is about 8 bits from the nearest 36h11 word) is out.
  Code hard = 0;
  for (const float v : reading.confidence) hard = (hard << 1) | (v > 0 ? 1u : 0u);
  if (family.nearest_word(hard, opt.max_bit_errors).index < 0) return std::nullopt;  // the chunk index
  const SoftMatch m = soft_match(family, reading.confidence, opt);
  if (m.best < 0 || m.second < 0 || m.best_bit_errors > opt.max_bit_errors || !(m.best_distance <= opt.max_distance) ||
      !(m.second_distance - m.best_distance >= opt.min_gap))
    return std::nullopt;
  return DecodeResult{m.best / 4, m.best_bit_errors, m.best % 4};
}

}  // namespace tagbench
