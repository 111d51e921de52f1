#pragma once
// Beyond the paper: what a minimum decision margin (DetectorOptions::min_decision_margin) buys
// against false detections on natural images, and what it costs in real detections.
//
// Our detector runs once at margin 0 on every corpus image (false side: the corpus holds no tags)
// and on ray-traced frames of the same family (true side: the distance sweep, whose far end is where
// payload reads get marginal, and image conditions such as sensor noise and blur). Every detection
// carries its decision margin, and the option filters the final detections, so scoring the one run
// at threshold m gives exactly what a run with min_decision_margin = m gives (tested in
// detect/tests/test_detector_inputs.cpp); every threshold is scored from the same detections.
//
// True side, per frame: detected at m when the right-id detection the sweep reports has a decision
// margin >= m. "Parts" of the true side: "distance" (the distance sweep), and each condition of the
// conditions sweep by name ("noise", "blur", ...); a part's rate is over all its frames (every step or
// strength). range_m: the largest distance up to which every distance step is detected in at least
// 90 % of its frames (0 when the nearest step is not).
#include <string>
#include <vector>

#include "fp_detectors.hpp"
#include "raytrace/sweeps.hpp"
#include "stats.hpp"

namespace tagbench::bench {

// 0, 0.05, ..., 0.95.
std::vector<double> default_margin_thresholds();

// Throws std::invalid_argument (one line) unless the thresholds are given, in [0, 1] and ascending
// without repeats.
void check_margin_thresholds(const std::vector<double>& thresholds);

// The detector whose detections are scored (our detector at its defaults, margin 0).
inline constexpr const char* kMarginDetector = "tagbench-paper";

struct MarginPartStats {
  std::string part;                // "distance" or a condition name
  std::uint64_t frames = 0, detected = 0;
  double rate = 0;
  Interval rate_ci;                // Wilson 95 %
  double range_m = 0;              // distance part only (NaN for the others)
};

struct MarginSummaryRow {
  std::string family;
  double threshold = 0;
  // False side (images readable in the corpus run).
  std::uint64_t images = 0;
  double megapixels = 0;
  std::uint64_t false_detections = 0, images_with_false = 0;
  double fp_per_image = 0, image_share = 0;
  Interval fp_per_image_ci, image_share_ci;  // exact Poisson; Wilson
  std::vector<MarginPartStats> parts;        // the true side, in the sweeps' order
};

struct MarginStepRow {
  std::string family;
  double threshold = 0;
  std::string part, step_unit;  // step_unit: "m" for distance, the condition's unit otherwise
  double step = 0;
  std::uint64_t frames = 0, detected = 0;
  double rate = 0;
  Interval rate_ci;
  double black_square_px_median = 0;
};

struct MarginTradeoff {
  std::vector<MarginSummaryRow> summary;  // family (as given), then threshold (ascending)
  std::vector<MarginStepRow> steps;       // family, threshold, part, step
};

struct MarginFamilySweeps {
  std::string family;
  std::vector<SweepResult> sweeps;  // distance and/or conditions sweeps of this family, kMarginDetector among their detectors
};

// Scores every threshold. fp: a run with kMarginDetector over the families (others' rows are
// ignored). Throws std::invalid_argument for thresholds check_margin_thresholds refuses, a family
// without the corpus run, or a sweep of another family or without kMarginDetector.
MarginTradeoff margin_tradeoff(const FpDetectorsRun& fp, const std::vector<MarginFamilySweeps>& sweeps,
                               const std::vector<double>& thresholds);

// margin_tradeoff.csv: family, detector, threshold, images, megapixels, false_detections,
// fp_per_image (+ ci95_lo/hi), images_with_false, image_share (+ ci95_lo/hi), then per part P:
// P_frames, P_detected, P_rate, P_rate_ci95_lo, P_rate_ci95_hi, and distance_range_m.
std::string margin_summary_csv(const MarginTradeoff& t);
// margin_tradeoff_steps.csv: family, detector, threshold, part, step, step_unit, frames, detected,
// rate, rate_ci95_lo, rate_ci95_hi, black_square_px_median.
std::string margin_steps_csv(const MarginTradeoff& t);

}  // namespace tagbench::bench
