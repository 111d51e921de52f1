#pragma once
// Halton low-discrepancy points (the 6-DoF sweep's samples): dimension d (0-based) is the radical
// inverse of the point's index in the d-th prime base (2, 3, 5, 7, 11, 13, 17, 19, ...).
//
// Scrambling: every digit position of every dimension has its own permutation of the base's digits,
// drawn from a seed (a random-digit-permutation scramble). It keeps what makes the sequence
// low-discrepancy (the first b^k points of a dimension still fall one into each interval
// [j / b^k, (j + 1) / b^k), and the first 2^a 3^c points of bases 2 and 3 one into each cell of that
// grid), and breaks the plain sequence's correlation between neighbouring large bases (11 and 13 draw
// the same diagonal lines for the first hundreds of points). Seed 0: no scramble (identity permutations).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tagbench::bench {

// The first n primes.
std::vector<int> first_primes(std::size_t n);

// The radical inverse of `index` in `base` (>= 2): its base-b digits mirrored about the point, in [0, 1).
double radical_inverse(std::uint64_t index, int base);

class Halton {
 public:
  // `dimensions` > 0; throws std::invalid_argument otherwise.
  Halton(std::size_t dimensions, std::uint64_t seed);
  std::size_t dimensions() const { return bases_.size(); }
  int base(std::size_t d) const { return bases_[d]; }
  std::uint64_t seed() const { return seed_; }
  // The point of this index, each coordinate in [0, 1).
  std::vector<double> point(std::uint64_t index) const;
  double coordinate(std::uint64_t index, std::size_t d) const;

 private:
  std::vector<int> bases_;
  std::uint64_t seed_;
  // perms_[d][k * base + digit]: the digit written at position k (k = 0 is the 1/b place).
  std::vector<std::vector<int>> perms_;
  std::vector<int> positions_;  // digit positions used per dimension (until b^-k is below 2^-53)
};

}  // namespace tagbench::bench
