// Halton points with a seeded random-digit-permutation scramble (halton.hpp).
#include "raytrace/halton.hpp"

#include <numeric>
#include <stdexcept>

#include "raytrace/sweep_detail.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

std::vector<int> first_primes(std::size_t n) {
  std::vector<int> p;
  for (int c = 2; p.size() < n; ++c) {
    bool prime = true;
    for (const int q : p) {
      if (q * q > c) break;
      if (c % q == 0) {
        prime = false;
        break;
      }
    }
    if (prime) p.push_back(c);
  }
  return p;
}

double radical_inverse(std::uint64_t index, int base) {
  if (base < 2) throw std::invalid_argument("radical_inverse: base must be >= 2");
  const auto b = static_cast<std::uint64_t>(base);
  double value = 0, f = 1.0 / base;
  for (; index > 0; index /= b, f /= base) value += static_cast<double>(index % b) * f;
  return value;
}

Halton::Halton(std::size_t dimensions, std::uint64_t seed) : seed_(seed) {
  if (dimensions == 0) throw std::invalid_argument("Halton: at least one dimension");
  bases_ = first_primes(dimensions);
  for (std::size_t d = 0; d < dimensions; ++d) {
    const int b = bases_[d];
    int k = 0;
    for (double f = 1; f > 0x1.0p-53; f /= b) ++k;  // digits beyond these change nothing in a double
    positions_.push_back(k);
    std::vector<int> perm(static_cast<std::size_t>(k * b));
    Rng rng{derive(seed, d + 1)};
    for (int pos = 0; pos < k; ++pos) {
      const auto first = perm.begin() + pos * b;
      std::iota(first, first + b, 0);
      if (seed == 0) continue;
      for (int i = b - 1; i > 0; --i)  // Fisher-Yates
        std::swap(first[i], first[static_cast<long>(rng.next() % static_cast<std::uint64_t>(i + 1))]);
    }
    perms_.push_back(std::move(perm));
  }
}

double Halton::coordinate(std::uint64_t index, std::size_t d) const {
  const int b = bases_.at(d);
  const auto ub = static_cast<std::uint64_t>(b);
  const std::vector<int>& perm = perms_[d];
  double value = 0, f = 1.0 / b;
  for (int pos = 0; pos < positions_[d]; ++pos, f /= b) {  // every position: a permuted 0 need not be 0
    value += perm[static_cast<std::size_t>(pos * b) + static_cast<std::size_t>(index % ub)] * f;
    index /= ub;
  }
  return value < 1 ? value : std::nextafter(1.0, 0.0);  // rounding could reach 1 when all digits are b - 1
}

std::vector<double> Halton::point(std::uint64_t index) const {
  std::vector<double> p;
  for (std::size_t d = 0; d < bases_.size(); ++d) p.push_back(coordinate(index, d));
  return p;
}

}  // namespace tagbench::bench
