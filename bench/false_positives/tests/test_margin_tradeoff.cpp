// The decision-margin trade-off scored on runs made here: false detections and ray-traced frames with
// known margins, so every count at every threshold is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "margin_tradeoff.hpp"

namespace test_margin_tradeoff {

using namespace tagbench;
using namespace tagbench::bench;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

corpus::CandidateImage image(const std::string& file, int w, int h, const std::string& status = "ok") {
  corpus::CandidateImage i;
  i.file = file;
  i.width = w;
  i.height = h;
  i.status = status;
  return i;
}

FalseDetection false_detection(std::uint32_t image, const std::string& detector, const std::string& family,
                               double margin) {
  FalseDetection d;
  d.image = image;
  d.detector = detector;
  d.family = family;
  d.decision_margin = margin;
  return d;
}

// Three images (the third unreadable). 16h5: margins 0.05 and 0.1 in image 0, 0.3 and 0.9 in image 1;
// one in the unreadable image and one of another detector, which count nowhere.
FpDetectorsRun corpus_run() {
  FpDetectorsRun r;
  r.options.detectors = {"tagbench-paper", "libapriltag-d2"};
  r.options.families = {"16h5", "25h9"};
  r.images = {image("a.png", 1000, 1000), image("b.png", 500, 200), image("c.png", 0, 0, "unreadable")};
  r.detections = {false_detection(0, "tagbench-paper", "16h5", 0.05), false_detection(0, "tagbench-paper", "16h5", 0.1),
                  false_detection(1, "tagbench-paper", "16h5", 0.3),  false_detection(1, "tagbench-paper", "16h5", 0.9),
                  false_detection(2, "tagbench-paper", "16h5", 0.99), false_detection(0, "libapriltag-d2", "16h5", 50),
                  false_detection(1, "tagbench-paper", "25h9", 0.2)};
  return r;
}

// A sweep with given (step, detected, margin) per frame of tagbench-paper, and an aruco row per frame
// (always detected, no margin) that must not count.
SweepResult sweep(Experiment e, const std::string& family, Condition c,
                  const std::vector<std::tuple<double, bool, double>>& frames) {
  SweepResult r;
  r.settings.experiment = e;
  r.settings.family = family;
  r.settings.detectors = {"tagbench-paper", "aruco"};
  for (const auto& [step, detected, margin] : frames) {
    SweepFrame f;
    f.condition = c;
    f.step = step;
    f.truth.black_square_px = 400.0 / step;
    r.frames.push_back(f);
    SweepRow ours;
    ours.frame = r.frames.size() - 1;
    ours.detector = "tagbench-paper";
    ours.detected_right_id = detected;
    ours.decision_margin = margin;
    r.rows.push_back(ours);
    SweepRow other = ours;
    other.detector = "aruco";
    other.detected_right_id = true;
    other.decision_margin = kNaN;
    r.rows.push_back(other);
  }
  return r;
}

MarginFamilySweeps family_sweeps(const std::string& family) {
  MarginFamilySweeps s;
  s.family = family;
  // Distance: 2 m both read clearly; 3 m one at 0.6, one missed; 4 m at 0.2 and 0.08.
  s.sweeps.push_back(sweep(Experiment::kDistance, family, Condition::kNone,
                           {{2, true, 0.95}, {2, true, 0.9}, {3, true, 0.6}, {3, false, kNaN}, {4, true, 0.2},
                            {4, true, 0.08}}));
  // Noise: strength 0 at 1.0, strength 8 at 0.4.
  s.sweeps.push_back(sweep(Experiment::kConditions, family, Condition::kNoise, {{0, true, 1.0}, {8, true, 0.4}}));
  return s;
}

const MarginSummaryRow& row(const MarginTradeoff& t, const std::string& family, double m) {
  for (const auto& r : t.summary)
    if (r.family == family && r.threshold == m) return r;
  throw std::runtime_error("no row " + family);
}

}  // namespace

TEST(MarginTradeoff, EveryThresholdCountsWhatADetectorWithThatMinimumWouldKeep) {
  const std::vector<double> th{0, 0.1, 0.5, 0.95};
  const MarginTradeoff t = margin_tradeoff(corpus_run(), {family_sweeps("16h5"), family_sweeps("25h9")}, th);
  ASSERT_EQ(t.summary.size(), 8u);
  const double mp = 1.0 + 0.1;
  struct Want {
    double m;
    std::uint64_t fp, images_with;
    std::uint64_t distance_detected, noise_detected;
    double range;
  };
  // Distance at 0: 2 m 2/2, 3 m 1/2 (< 90 %), 4 m 2/2 -> range 2 m; at 0.95: 2 m 1/2 -> range 0.
  for (const Want& w : {Want{0, 4, 2, 5, 2, 2}, Want{0.1, 3, 2, 4, 2, 2}, Want{0.5, 1, 1, 3, 1, 2},
                        Want{0.95, 0, 0, 1, 1, 0}}) {
    const auto& r = row(t, "16h5", w.m);
    EXPECT_EQ(r.images, 2u);
    EXPECT_DOUBLE_EQ(r.megapixels, mp);
    EXPECT_EQ(r.false_detections, w.fp) << w.m;
    EXPECT_EQ(r.images_with_false, w.images_with) << w.m;
    EXPECT_DOUBLE_EQ(r.fp_per_image, w.fp / 2.0);
    EXPECT_DOUBLE_EQ(r.image_share, w.images_with / 2.0);
    EXPECT_LE(r.fp_per_image_ci.lo, r.fp_per_image);
    EXPECT_GT(r.fp_per_image_ci.hi, r.fp_per_image);
    ASSERT_EQ(r.parts.size(), 2u);
    EXPECT_EQ(r.parts[0].part, "distance");
    EXPECT_EQ(r.parts[0].frames, 6u);
    EXPECT_EQ(r.parts[0].detected, w.distance_detected) << w.m;
    EXPECT_DOUBLE_EQ(r.parts[0].rate, w.distance_detected / 6.0);
    EXPECT_DOUBLE_EQ(r.parts[0].range_m, w.range) << w.m;
    EXPECT_EQ(r.parts[1].part, "noise");
    EXPECT_EQ(r.parts[1].frames, 2u);
    EXPECT_EQ(r.parts[1].detected, w.noise_detected) << w.m;
    EXPECT_TRUE(std::isnan(r.parts[1].range_m));
    // 25h9: one false detection at 0.2; the same frames.
    const auto& q = row(t, "25h9", w.m);
    EXPECT_EQ(q.false_detections, w.m <= 0.2 ? 1u : 0u) << w.m;
    EXPECT_EQ(q.parts[0].detected, w.distance_detected);
  }
  // Per step: 16h5 at 0.5: 2 m 2/2, 3 m 1/2, 4 m 0/2; noise 0: 1/1, 8: 0/1.
  std::vector<std::pair<double, std::uint64_t>> got;
  for (const auto& s : t.steps)
    if (s.family == "16h5" && s.threshold == 0.5) {
      got.emplace_back(s.step, s.detected);
      EXPECT_EQ(s.step_unit, s.part == "distance" ? "m" : "sigma_levels");
      if (s.part == "distance") {
        EXPECT_EQ(s.frames, 2u);
        EXPECT_DOUBLE_EQ(s.black_square_px_median, 400.0 / s.step);
      }
    }
  const std::vector<std::pair<double, std::uint64_t>> want{{2, 2}, {3, 1}, {4, 0}, {0, 1}, {8, 0}};
  EXPECT_EQ(got, want);

  // The files: a header naming the parts, a row per family and threshold; a row per step.
  const std::string csv = margin_summary_csv(t);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "family,detector,threshold,images,megapixels,false_detections,fp_per_image,fp_per_image_ci95_lo,"
            "fp_per_image_ci95_hi,images_with_false,image_share,image_share_ci95_lo,image_share_ci95_hi,"
            "distance_frames,distance_detected,distance_rate,distance_rate_ci95_lo,distance_rate_ci95_hi,"
            "noise_frames,noise_detected,noise_rate,noise_rate_ci95_lo,noise_rate_ci95_hi,distance_range_m");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 9);
  EXPECT_NE(csv.find("\n16h5,tagbench-paper,0.5,2,1.1,1,0.5,"), std::string::npos) << csv;
  const std::string steps = margin_steps_csv(t);
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 1 + 2 * 4 * 5);
}

TEST(MarginTradeoff, RefusesWhatCannotBeScored) {
  const auto fp = corpus_run();
  const auto s16 = family_sweeps("16h5");
  EXPECT_THROW(margin_tradeoff(fp, {s16}, {}), std::invalid_argument);
  EXPECT_THROW(margin_tradeoff(fp, {s16}, {0.5, 0.2}), std::invalid_argument);
  EXPECT_THROW(margin_tradeoff(fp, {s16}, {0.2, 0.2}), std::invalid_argument);
  EXPECT_THROW(margin_tradeoff(fp, {s16}, {0, 1.5}), std::invalid_argument);
  EXPECT_THROW(margin_tradeoff(fp, {s16}, {kNaN}), std::invalid_argument);
  EXPECT_THROW(margin_tradeoff(fp, {family_sweeps("36h11")}, {0}), std::invalid_argument);  // no corpus run
  MarginFamilySweeps wrong = s16;
  wrong.sweeps[0].settings.family = "25h9";
  EXPECT_THROW(margin_tradeoff(fp, {wrong}, {0}), std::invalid_argument);
  MarginFamilySweeps theirs = s16;
  theirs.sweeps[0].settings.detectors = {"aruco"};
  EXPECT_THROW(margin_tradeoff(fp, {theirs}, {0}), std::invalid_argument);
  FpDetectorsRun no_ours = fp;
  no_ours.options.detectors = {"libapriltag-d2"};
  EXPECT_THROW(margin_tradeoff(no_ours, {s16}, {0}), std::invalid_argument);
  EXPECT_EQ(default_margin_thresholds().size(), 20u);
  EXPECT_EQ(default_margin_thresholds().front(), 0);
  EXPECT_NEAR(default_margin_thresholds().back(), 0.95, 1e-12);
}

}  // namespace test_margin_tradeoff
