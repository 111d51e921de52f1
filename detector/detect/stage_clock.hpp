#pragma once
// The stages' wall-clock laps (StageTimings, milliseconds). Private to the library's .cpp files.
#include <chrono>

namespace tagbench::detail {

using StageClock = std::chrono::steady_clock;

// Milliseconds since `t`, and `t` moved to now (the next lap starts there).
inline double lap_ms(StageClock::time_point& t) {
  const auto now = StageClock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

}  // namespace tagbench::detail
