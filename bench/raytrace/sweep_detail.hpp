#pragma once
// What the sweep files share and nothing else needs: the portable randomness every trial's draws and the
// noise condition come from, and a few constants.
#include <cmath>
#include <cstdint>
#include <limits>

namespace tagbench::bench::sweep_detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kDeg = M_PI / 180;
inline constexpr double kConditionsMaxPhi = 30;  // conditions: phi uniform in [0, this] degrees

// ---- randomness: splitmix64, portable (no std:: distributions, whose outputs are library-defined) ----

inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

inline std::uint64_t derive(std::uint64_t a, std::uint64_t b) {
  std::uint64_t s = a ^ (b * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL);
  splitmix64(s);
  return splitmix64(s);
}

struct Rng {
  std::uint64_t state;
  std::uint64_t next() { return splitmix64(state); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double normal() {                                                            // Box-Muller
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }
};

}  // namespace tagbench::bench::sweep_detail
