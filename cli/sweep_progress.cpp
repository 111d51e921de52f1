#include "cli/sweep_progress.hpp"

#include <chrono>
#include <cstdio>
#include <optional>

#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace {

std::string describe(const SweepFrame& f, Experiment e) {
  char buf[160];
  if (e == Experiment::kAngle) std::snprintf(buf, sizeof buf, "phi %g deg, trial %d", f.step, f.trial);
  else if (e == Experiment::kDistance) std::snprintf(buf, sizeof buf, "distance %g m, trial %d", f.step, f.trial);
  else std::snprintf(buf, sizeof buf, "%s %g, trial %d", condition_name(f.condition), f.step, f.trial);
  return buf;
}

}  // namespace

RenderOptions render_options(const Args& a) {
  RenderOptions ro;
  ro.processes = static_cast<int>(a.get_int("processes", 0, 1, 256));
  ro.cache_dir = a.has("cache") ? std::filesystem::path(*a.get("cache")) : default_render_cache();
  ro.povray = a.get_or("povray", "povray");
  ro.max_frames_per_process = 50;  // an interrupted run loses at most this many frames per process
  return ro;
}

SweepResult run_sweep_with_progress(const SweepSettings& s, const RenderOptions& ro, const std::string& command,
                                    const std::string& label) {
  std::optional<ProgressBar> bar;
  SweepProgress progress;
  // The time left is estimated from the phase's start: the run's for rendering (its first report
  // comes after a whole povray batch), the first detection's for detecting.
  auto phase_start = std::chrono::steady_clock::now();
  const auto update = [&](const char* phase, const std::string& detail, std::size_t done, std::size_t total) {
    if (!bar) bar.emplace(label + ": " + phase);
    const double frac = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - phase_start).count();
    bar->update(frac, std::to_string(done) + "/" + std::to_string(total) + " frames", detail,
                frac > 0 ? el / frac * (1 - frac) : -1);
  };
  char render_detail[64], detect_detail[64];
  std::snprintf(render_detail, sizeof render_detail, "(%d povray processes)",
                ro.processes > 0 ? ro.processes : hardware_threads());
  std::snprintf(detect_detail, sizeof detect_detail, "(%zu detectors, one thread)", s.detectors.size());
  progress.render = [&](std::size_t done, std::size_t total) { update("rendering", render_detail, done, total); };
  constexpr std::size_t kFailuresShown = 10;  // one line each; the rest are counted (all are in the JSON)
  std::size_t failures = 0;
  progress.failed = [&](const SweepFrame& f, const std::string& error) {
    bar.reset();
    if (++failures <= kFailuresShown)
      std::fprintf(stderr, "%s: frame not rendered (%s): %s\n", command.c_str(), describe(f, s.experiment).c_str(),
                   error.c_str());
  };
  bool detecting = false;
  progress.detect = [&](std::size_t done, std::size_t total) {
    if (!detecting) {
      bar.reset();  // the render bar ends; the detection bar starts
      phase_start = std::chrono::steady_clock::now();
    }
    detecting = true;
    update("detecting", detect_detail, done, total);
  };
  SweepResult r = run_sweep(s, ro, progress);
  bar.reset();
  if (failures > kFailuresShown)
    std::fprintf(stderr, "%s: %zu more frames not rendered (listed in the JSON sidecar)\n", command.c_str(),
                 failures - kFailuresShown);
  return r;
}

}  // namespace tagbench::cli
