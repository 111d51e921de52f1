#pragma once
// The message plan_sweep refuses a setting with, for the sweep tests' bad-option cases.
#include <stdexcept>
#include <string>

#include "raytrace/sweeps.hpp"

namespace tagbench::bench::test {

inline std::string refusal(const SweepSettings& s) {
  try {
    plan_sweep(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(not refused)";
}

}  // namespace tagbench::bench::test
