// The run: render the planned frames, put every rendered frame through every detector, one row each.
#include <chrono>
#include <map>
#include <memory>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "raytrace/sweep_detail.hpp"
#include "raytrace/sweep_external.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

using DetectorSet = std::vector<std::unique_ptr<Comparator>>;

DetectorSet make_detectors(const SweepSettings& s, std::optional<std::array<double, 5>> distortion) {
  ComparatorSetup setup;
  setup.family = s.family;
  setup.camera = render_camera();
  setup.tag_size = *s.tag_size;
  setup.distortion = distortion;
  setup.input_gamma = 1;  // POV-Ray's frames are linear (File_Gamma=1.0, render.hpp)
  DetectorSet set;
  for (const auto& name : s.detectors)
    if (!find_external(s, name)) set.push_back(make_comparator(name, setup));  // the built-in ones, in order
  return set;
}

SweepRow row_of(const DetectorOutput& out, const std::string& detector, std::size_t index, const SweepFrame& f) {
  return score_frame(out.found, out.ms, detector, index, f);
}

}  // namespace

SweepRow score_frame(std::span<const Found> found, double ms, const std::string& detector, std::size_t index,
                     const SweepFrame& f, const Found** best_out) {
  SweepRow r;
  r.frame = index;
  r.detector = detector;
  r.ms = ms;
  r.orientation_error_deg = r.distance_error_m = r.distance_error_percent = r.corner_rms_px = kNaN;
  r.decision_margin = kNaN;
  const Found* best = nullptr;
  FoundErrors best_e;
  for (const Found& x : found) {
    const std::string& truth_family = f.frame.family_name.empty() ? f.frame.family : f.frame.family_name;
    if (x.id != f.frame.id || canonical_family_name(x.family) != canonical_family_name(truth_family)) {
      r.wrong_id = true;
      continue;
    }
    const FoundErrors e = found_errors(x, f.truth);
    if (!best || e.corner_rms_px < best_e.corner_rms_px) {
      best = &x;
      best_e = e;
    }
  }
  if (best) {
    r.detected_right_id = true;
    r.corner_rms_px = best_e.corner_rms_px;
    r.orientation_error_deg = best_e.orientation_deg;
    r.distance_error_m = best_e.distance_m;
    r.distance_error_percent = best_e.distance_percent;
    r.decision_margin = best->decision_margin;
  }
  if (best_out) *best_out = best;
  return r;
}

SweepResult run_sweep(const SweepSettings& settings, RenderOptions render_options, const SweepProgress& progress) {
  SweepResult res;
  res.settings = resolve_settings(settings);
  res.frames = plan_sweep(res.settings);
  const SweepSettings& s = res.settings;
  // The detectors of the sweep's lens (sixdof: its camera's; the others: the pinhole); a bad detector
  // setup fails before any rendering.
  DetectorSet plain = make_detectors(s, s.experiment == Experiment::kSixdof
                                            ? std::optional<std::array<double, 5>>(s.sixdof.distortion)
                                            : std::nullopt);
  std::vector<std::string> builtin_names;  // the built-in detectors, in the order of `plain`
  for (std::size_t k = 0, b = 0; k < s.detectors.size(); ++k) {
    if (find_external(s, s.detectors[k])) {
      res.can_explain.push_back(false);  // an external detector gives no loss stage
    } else {
      builtin_names.push_back(s.detectors[k]);
      res.can_explain.push_back(plain[b++]->can_explain());
    }
  }

  std::vector<FramePose> poses;
  poses.reserve(res.frames.size());
  for (const auto& f : res.frames) poses.push_back(f.frame);
  render_options.progress = progress.render;
  const RenderReport report = render_frames(poses, scene_template(s.scene), render_options);
  res.rendered = report.rendered;
  res.from_cache = report.from_cache;
  res.distinct_frames = report.rendered + report.from_cache + report.failed;
  res.povray_runs = report.povray_runs;
  res.render_seconds = report.seconds;
  for (std::size_t i = 0; i < res.frames.size(); ++i) {
    if (report.frames[i].ok()) continue;
    res.failed.push_back({i, report.frames[i].error});
    if (progress.failed) progress.failed(res.frames[i], report.frames[i].error);
  }
  if (!res.frames.empty() && res.failed.size() == res.frames.size())
    throw std::runtime_error("none of the " + std::to_string(res.frames.size()) +
                             " frames rendered: " + res.failed.front().error);

  const auto t0 = std::chrono::steady_clock::now();
  // The external detectors first, each once on all the frames: a failure leaves no rows at all.
  const std::vector<std::vector<DetectorOutput>> external = run_external_detectors(s, res.frames, report);
  // Where each detector's output is: the index into the built-in set's outputs, or into `external`.
  std::vector<std::pair<bool, std::size_t>> source;
  for (std::size_t k = 0, builtin = 0; k < s.detectors.size(); ++k) {
    if (const ExternalDetector* e = find_external(s, s.detectors[k]))
      source.emplace_back(true, static_cast<std::size_t>(e - s.external.data()));
    else
      source.emplace_back(false, builtin++);
  }
  const int saved_threads = cv::getNumThreads();
  cv::setNumThreads(1);
  struct Restore {
    int n;
    ~Restore() { cv::setNumThreads(n); }
  } restore{saved_threads};
  std::map<double, DetectorSet> distorted;             // per k1
  // An unmodified frame runs once (the conditions' zero-strength baselines share their render; same truth).
  struct FrameRun {
    std::vector<DetectorOutput> outputs;
    std::vector<SweepRow> rows;  // with their loss explanations
  };
  std::map<std::string, FrameRun> plain_runs;
  std::string gray_path;
  cv::Mat gray;
  const std::size_t total = res.frames.size() - res.failed.size();
  std::size_t done = 0;
  for (std::size_t i = 0; i < res.frames.size(); ++i) {
    if (!report.frames[i].ok()) continue;
    const SweepFrame& f = res.frames[i];
    const std::string png = report.frames[i].png.string();
    const bool unmodified = frame_unmodified(f);
    const FrameRun* run = nullptr;
    FrameRun fresh;
    if (unmodified) {
      if (auto it = plain_runs.find(png); it != plain_runs.end()) run = &it->second;
    }
    if (!run) {
      if (png != gray_path) {
        gray = read_frame_gray(png);
        gray_path = png;
      }
      const cv::Mat image = apply_effect(gray, f);
      DetectorSet* set = &plain;
      if (f.effect.condition == Condition::kDistortion && f.effect.strength != 0) {
        const double k1 = -f.effect.strength;
        auto it = distorted.find(k1);
        if (it == distorted.end())
          it = distorted.emplace(k1, make_detectors(s, std::array<double, 5>{k1, 0, 0, 0, 0})).first;
        set = &it->second;
      }
      for (auto& det : *set) fresh.outputs.push_back(det->run(image));
      // Explanations after every detector has run and been timed: a missed frame is detected again, with a trace.
      for (std::size_t k = 0; k < set->size(); ++k) {
        fresh.rows.push_back(row_of(fresh.outputs[k], builtin_names[k], i, f));
        if (!fresh.rows.back().detected_right_id)
          fresh.rows.back().loss = (*set)[k]->explain(image, f.frame.family, f.frame.id, f.truth.corners);
      }
      if (unmodified) run = &plain_runs.emplace(png, std::move(fresh)).first->second;
      else run = &fresh;
    }
    for (std::size_t k = 0; k < s.detectors.size(); ++k) {  // the detectors' order, external ones in their place
      const auto [is_external, j] = source[k];
      SweepRow row = is_external ? row_of(external[j][i], s.detectors[k], i, f) : run->rows[j];
      row.frame = i;
      res.rows.push_back(std::move(row));
    }
    ++done;
    if (progress.detect) progress.detect(done, total);
  }
  res.detect_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace tagbench::bench
