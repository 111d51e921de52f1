#pragma once
// The settings of a small sweep, for the sweep tests (test_sweep_plans.cpp, test_sweep_runs.cpp), and
// the message plan_sweep refuses a setting with, for the sweep tests' bad-option cases.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "raytrace/sweeps.hpp"

namespace tagbench::bench::test {

// `trials` trials of experiment `e` at `steps` (none given: the experiment's default steps).
inline SweepSettings settings(Experiment e, int trials, std::vector<double> steps = {}) {
  SweepSettings s;
  s.experiment = e;
  s.trials = trials;
  s.steps = std::move(steps);
  return s;
}

inline std::string refusal(const SweepSettings& s) {
  try {
    plan_sweep(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(not refused)";
}

}  // namespace tagbench::bench::test
