#pragma once
// java.util.Random, just enough to seed the lexicode generator like the original (docs/paper-to-code.md section 2):
// a 48-bit linear congruential generator; nextLong() = (next(32) << 32) + next(32), the second int
// sign-extended.
#include <cstdint>

namespace tagbench {

class JavaRandom {
 public:
  explicit JavaRandom(std::int64_t seed)
      : state_((static_cast<std::uint64_t>(seed) ^ kMultiplier) & kMask) {}

  std::int32_t next(int bits) {
    state_ = (state_ * kMultiplier + 0xB) & kMask;
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(state_ >> (48 - bits)));
  }

  std::int64_t next_long() {
    const auto hi = static_cast<std::uint64_t>(static_cast<std::int64_t>(next(32))) << 32;
    const auto lo = static_cast<std::uint64_t>(static_cast<std::int64_t>(next(32)));  // sign-extended
    return static_cast<std::int64_t>(hi + lo);
  }

 private:
  static constexpr std::uint64_t kMultiplier = 0x5DEECE66DULL;
  static constexpr std::uint64_t kMask = (std::uint64_t{1} << 48) - 1;
  std::uint64_t state_;
};

}  // namespace tagbench
