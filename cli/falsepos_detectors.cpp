// tagbench falsepos detectors and margin (cmd_falsepos.cpp has the help): whole detectors at their
// defaults on the natural-image corpus, and what a minimum decision margin buys (fewer false
// detections there) and costs (fewer detections of ray-traced tags).
#include "cli/falsepos_detectors.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "candidates.hpp"
#include "cli/sweep_args.hpp"
#include "cli/sweep_progress.hpp"
#include "fp_detectors.hpp"
#include "margin_tradeoff.hpp"
#include "raytrace/comparators.hpp"
#include "raytrace/sweeps.hpp"
#include "tools/atomic_file.hpp"
#include "tools/json.hpp"
#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace {

// --corpus DIR: required, an existing folder.
std::string corpus_arg(const Args& a) {
  const auto dir = a.get("corpus");
  if (!dir) throw UsageError("--corpus DIR is required");
  if (!std::filesystem::is_directory(*dir)) throw UsageError("--corpus " + *dir + ": " + why_not_directory(*dir));
  return *dir;
}

// run_fp_detectors with a progress bar (count, detections, time left). Images run in parallel there;
// OpenCV's own thread pool (aruco) would only oversubscribe the cores, so it is set to one thread.
FpDetectorsRun fp_detectors_with_progress(const std::string& corpus_dir, std::vector<corpus::CandidateImage> images,
                                          const FpDetectorsOptions& o, const std::string& label) {
  cv::setNumThreads(1);
  ProgressBar bar(label);
  const auto t0 = std::chrono::steady_clock::now();
  return run_fp_detectors(corpus_dir, std::move(images), o, [&](const FpDetectorsProgress& p) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double rate = s > 0 ? static_cast<double>(p.images_done) / s : 0;
    const double left = rate > 0 ? static_cast<double>(p.images_total - p.images_done) / rate : -1;
    bar.update(p.images_total ? static_cast<double>(p.images_done) / static_cast<double>(p.images_total) : 1.0,
               std::to_string(p.images_done) + "/" + std::to_string(p.images_total),
               std::to_string(p.detections) + " detections", left);
  });
}

}  // namespace

namespace falsepos_cmd {

int falsepos_detectors(const Words& w) {
  const Args a(w, {{"corpus"}, {"out"}, {"detectors"}, {"families"}, {"jobs"}, {"external-timeout"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = out_dir(a);
  const std::string corpus_dir = corpus_arg(a);
  FpDetectorsOptions o;
  o.jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  if (auto v = a.get("detectors")) {
    o.detectors.clear();
    parse_detector_list("--detectors", *v, a.get_double("external-timeout", 1800, 1e-3, 1e9), o.detectors, o.external);
  } else if (a.has("external-timeout")) {
    throw UsageError("--external-timeout: no external detector (--detectors ...,external:NAME=COMMAND)");
  }
  if (auto v = a.get("families")) o.families = option_list("--families", *v);
  if (o.detectors.empty()) throw UsageError("--detectors: empty list");
  for (const auto& d : o.detectors)
    for (const auto& f : o.families) try {
        if (std::any_of(o.external.begin(), o.external.end(), [&](const auto& e) { return e.name == d; })) continue;
        ComparatorSetup s;
        s.family = f;
        make_comparator(d, s);
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--detectors/--families: ") + e.what());
      }
  auto images = corpus::corpus_images(corpus_dir);
  if (images.empty()) throw std::runtime_error(corpus_dir + ": no images");
  const auto t0 = std::chrono::steady_clock::now();
  const FpDetectorsRun run = fp_detectors_with_progress(corpus_dir, std::move(images), o, "false positives");
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto rows = fp_detector_rows(run);
  std::size_t unreadable = 0;
  for (const auto& i : run.images) unreadable += i.status != "ok";
  std::ostringstream js;
  js << "{\n  \"command\": \"tagbench falsepos detectors\",\n  \"corpus\": " << json_string(corpus_dir)
     << ",\n  \"images\": " << run.images.size() << ",\n  \"images_unreadable\": " << unreadable
     << ",\n  \"detectors\": {\n"
        "    \"tagbench\": \"tagbench default profile (DetectorOptions defaults: threshold quads, edge refinement, "
        "area payload reading, bits corrected by family (16h5 1, 25h9 2, 36h11 3), full resolution)\",\n"
        "    \"tagbench-thorough\": \"tagbench DetectorOptions::thorough() (the default profile with its quads from "
        "straight edges found at full resolution, line_quads, and the coarse pass, coarse_pass)\",\n"
        "    \"tagbench-half\": \"tagbench default profile, quads found at half resolution\",\n"
        "    \"tagbench-paper\": \"tagbench DetectorOptions::paper() (sigma 0.8, 1 bit corrected, full resolution)\",\n"
        "    \"tagbench-paper-half\": \"tagbench DetectorOptions::paper(), segmentation at half resolution\",\n"
        "    \"libapriltag-d1\": \"libapriltag 3.3: quad_decimate 1, its other defaults, 2 bits corrected\",\n"
        "    \"libapriltag-d2\": \"libapriltag 3.3 defaults: quad_decimate 2, refine_edges 1, decode_sharpening 0.25, "
        "2 bits corrected\",\n"
        "    \"aruco\": \"OpenCV 4.6 aruco DICT_APRILTAG_*, CORNER_REFINE_APRILTAG\",\n"
        "    \"aruco-default\": \"OpenCV 4.6 aruco DICT_APRILTAG_*, DetectorParameters defaults\"\n  },\n"
     << "  \"run\": [";
  for (std::size_t i = 0; i < o.detectors.size(); ++i) js << (i ? ", " : "") << json_string(o.detectors[i]);
  if (!o.external.empty()) {  // only then: the built-in runs' sidecars keep their bytes
    js << "],\n  \"external\": [";
    for (std::size_t i = 0; i < o.external.size(); ++i)
      js << (i ? ", " : "") << "{\"name\": " << json_string(o.external[i].name)
         << ", \"command\": " << json_string(o.external[i].command) << "}";
  }
  js << "],\n  \"families\": [";
  for (std::size_t i = 0; i < o.families.size(); ++i) js << (i ? ", " : "") << json_string(o.families[i]);
  js << "],\n  \"jobs\": " << o.jobs << ",\n  \"wall_seconds\": " << secs
     << ",\n  \"cpu\": " << json_string(cpu_model_name()) << "\n}\n";
  write_files_atomic({{dir / "fp_detectors.csv", fp_detectors_csv(rows)},
                      {dir / "fp_detections.csv", fp_detections_csv(run)},
                      {dir / "fp_detectors.json", js.str()}});
  std::fprintf(stderr,
               "tagbench falsepos detectors: %zu images (%zu unreadable), %zu false detections in %.1f s; wrote "
               "fp_detectors.csv, fp_detections.csv, fp_detectors.json in %s\n",
               run.images.size(), unreadable, run.detections.size(), secs, dir.string().c_str());
  return 0;
}

int falsepos_margin(const Words& w) {
  const Args a(w, {{"corpus"}, {"out"}, {"families"}, {"thresholds"}, {"trials"}, {"seed"}, {"distances"}, {"conditions"},
                   {"cache"}, {"processes"}, {"povray"}, {"jobs"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = out_dir(a);
  const std::string corpus_dir = corpus_arg(a);
  FpDetectorsOptions o;
  o.jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  o.detectors = {kMarginDetector};
  o.families = {"16h5", "25h9"};
  if (auto v = a.get("families")) o.families = option_list("--families", *v);
  std::vector<double> thresholds = default_margin_thresholds();
  if (auto v = a.get("thresholds")) {
    thresholds.clear();
    for (const auto& t : option_list("--thresholds", *v)) thresholds.push_back(parse_double("--thresholds", t, 0, 1));
  }
  const int trials = static_cast<int>(a.get_int("trials", 10, 1, 100000));
  const auto seed = static_cast<std::uint64_t>(a.get_int("seed", 1, 0, (1LL << 62)));
  std::vector<Condition> conditions{Condition::kNoise, Condition::kBlur};
  if (auto v = a.get("conditions")) {
    conditions.clear();
    if (*v != "none") try {
        for (const auto& c : option_list("--conditions", *v)) conditions.push_back(parse_condition(c));
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--conditions: ") + e.what());
      }
  }
  // Every setting is checked before any work: the sweeps' plans (family, conditions), the thresholds.
  std::vector<std::pair<std::string, std::vector<SweepSettings>>> plans;
  try {
    check_margin_thresholds(thresholds);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--thresholds: ") + e.what());
  }
  try {
    for (const auto& f : o.families) {
      std::vector<SweepSettings> v;
      SweepSettings d;
      d.experiment = Experiment::kDistance;
      d.trials = trials;
      d.seed = seed;
      d.detectors = {kMarginDetector};
      d.family = f;
      if (auto list = a.get("distances")) {
        for (const auto& x : option_list("--distances", *list)) d.steps.push_back(parse_double("--distances", x, -1e300, 1e300));
      } else {
        // The distance sweep's steps from 3 m: at 2 m the whole printed tag of a family with a wider
        // white border than 36h11's (16h5: 8 cells for a 6-cell black square) may leave the image.
        for (const double x : default_steps(Experiment::kDistance))
          if (x >= 3) d.steps.push_back(x);
      }
      v.push_back(d);
      if (!conditions.empty()) {
        SweepSettings c = d;
        c.experiment = Experiment::kConditions;
        c.steps.clear();  // the conditions have their strengths
        c.conditions = conditions;
        v.push_back(c);
      }
      for (auto& s : v) {
        s = resolve_settings(s);
        plan_sweep(s);
      }
      plans.emplace_back(f, std::move(v));
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const RenderOptions ro = render_options(a);
  auto images = corpus::corpus_images(corpus_dir);
  if (images.empty()) throw std::runtime_error(corpus_dir + ": no images");

  const auto t0 = std::chrono::steady_clock::now();
  // The true side first: a missing POV-Ray fails before the long corpus run.
  std::vector<MarginFamilySweeps> sweeps;
  for (const auto& [family, settings] : plans) {
    MarginFamilySweeps fs;
    fs.family = family;
    for (const auto& s : settings)
      fs.sweeps.push_back(run_sweep_with_progress(s, ro, "tagbench falsepos margin",
                                                  "margin " + family + " " + experiment_name(s.experiment)));
    sweeps.push_back(std::move(fs));
  }
  const FpDetectorsRun run = fp_detectors_with_progress(corpus_dir, std::move(images), o, "margin: corpus");
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MarginTradeoff t;
  try {
    t = margin_tradeoff(run, sweeps, thresholds);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  std::size_t unreadable = 0, failed_frames = 0;
  for (const auto& i : run.images) unreadable += i.status != "ok";
  std::ostringstream js;
  js << "{\n  \"command\": \"tagbench falsepos margin\",\n  \"corpus\": " << json_string(corpus_dir)
     << ",\n  \"images\": " << run.images.size() << ",\n  \"images_unreadable\": " << unreadable
     << ",\n  \"detector\": \"" << kMarginDetector
     << "\",\n  \"detector_settings\": \"tagbench DetectorOptions::paper() (sigma 0.8, 1 bit corrected, full "
        "resolution), min_decision_margin 0; thresholds applied to the final detections\",\n  \"families\": [";
  for (std::size_t i = 0; i < o.families.size(); ++i) js << (i ? ", " : "") << json_string(o.families[i]);
  js << "],\n  \"thresholds\": " << json_numbers(thresholds) << ",\n  \"sweeps\": [\n";
  bool first = true;
  for (const auto& fs : sweeps)
    for (const auto& r : fs.sweeps) {
      failed_frames += r.failed.size();
      std::string conds;
      for (const auto c : r.settings.conditions) conds += (conds.empty() ? "\"" : ", \"") + std::string(condition_name(c)) + "\"";
      js << (first ? "" : ",\n") << "    {\"family\": " << json_string(fs.family) << ", \"experiment\": \""
         << experiment_name(r.settings.experiment) << "\", \"conditions\": [" << conds
         << "], \"trials\": " << r.settings.trials << ", \"seed\": " << r.settings.seed
         << ", \"tag_size_m\": " << *r.settings.tag_size << ", \"steps\": " << json_numbers(r.settings.steps)
         << ", \"frames\": " << r.frames.size() << ", \"failed_frames\": " << r.failed.size() << "}";
      first = false;
    }
  js << "\n  ],\n  \"range_rule\": \"distance_range_m: the largest distance up to which every distance step is "
        "detected in at least 90 % of its frames\",\n  \"jobs\": "
     << o.jobs << ",\n  \"wall_seconds\": " << secs << ",\n  \"cpu\": " << json_string(cpu_model_name()) << "\n}\n";
  write_files_atomic({{dir / "margin_tradeoff.csv", margin_summary_csv(t)},
                      {dir / "margin_tradeoff_steps.csv", margin_steps_csv(t)},
                      {dir / "margin_tradeoff.json", js.str()}});
  std::fprintf(stderr,
               "tagbench falsepos margin: %zu images (%zu unreadable), %zu false detections at margin 0, %zu "
               "thresholds, %zu ray-traced frames not rendered, %.1f s; wrote margin_tradeoff.csv, "
               "margin_tradeoff_steps.csv, margin_tradeoff.json in %s\n",
               run.images.size(), unreadable, run.detections.size(), thresholds.size(), failed_frames, secs,
               dir.string().c_str());
  return 0;
}

}  // namespace falsepos_cmd

}  // namespace tagbench::cli
