// Detector speed (issue 3, section 4): ours per stage and whole, full and half resolution, beside
// libapriltag 3 (decimate 1 and 2) and OpenCV aruco (DICT_APRILTAG_36h11, CORNER_REFINE_APRILTAG) on
// the same synthetic scenes, all single-threaded. `make bench` turns the report into results/speed.csv.
#include <benchmark/benchmark.h>

#include <map>

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <opencv2/aruco.hpp>
#include <opencv2/core.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "scenes.hpp"

namespace {

using namespace tagbench;
using namespace tagbench::bench;

const cv::Mat& scene(int w, int h) {
  static std::map<std::pair<int, int>, cv::Mat> cache;  // benchmarks run sequentially
  auto& m = cache[{w, h}];
  if (m.empty()) m = make_scene(w, h, "36h11", 6, 1234).image;
  return m;
}

void BM_Ours(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  DetectorOptions o = DetectorOptions::paper();
  o.families = {"36h11"};
  o.half_resolution = state.range(2) == 1;
  if (state.range(2) == 2) o.quad_search.close_enough = CloseEnoughRule::kCode2012;
  const Detector det(o);
  const cv::Mat& img = scene(w, h);
  // As a video stream is processed: one workspace, so the per-pixel buffers are allocated once
  // (the first, untimed iteration of Google Benchmark's estimate warms it).
  DetectorWorkspace ws;
  StageTimings sum;
  std::size_t found = 0, segments = 0, quads = 0;
  for (auto _ : state) {
    StageTimings t;
    const auto d = detect(det, img, ws, nullptr, &t);
    found = d.size();
    segments = t.segment_count;
    quads = t.quad_count;
    sum.blur += t.blur;
    sum.gradient += t.gradient;
    sum.segmentation += t.segmentation;
    sum.line_fit += t.line_fit;
    sum.quads += t.quads;
    sum.decode += t.decode;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["detections"] = static_cast<double>(found);
  state.counters["segments"] = static_cast<double>(segments);
  state.counters["candidate_quads"] = static_cast<double>(quads);
  state.counters["blur_ms"] = sum.blur / n;
  state.counters["gradient_ms"] = sum.gradient / n;
  state.counters["segmentation_ms"] = sum.segmentation / n;
  state.counters["line_fit_ms"] = sum.line_fit / n;
  state.counters["quads_ms"] = sum.quads / n;
  state.counters["decode_ms"] = sum.decode / n;
}

void BM_AprilTag3(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  apriltag_family_t* tf = tag36h11_create();
  apriltag_detector_t* td = apriltag_detector_create();
  apriltag_detector_add_family(td, tf);
  td->quad_decimate = static_cast<float>(state.range(2));
  td->nthreads = 1;
  const cv::Mat& img = scene(w, h);
  image_u8_t im{img.cols, img.rows, static_cast<std::int32_t>(img.step), img.data};
  int found = 0;
  for (auto _ : state) {
    zarray_t* dets = apriltag_detector_detect(td, &im);
    found = zarray_size(dets);
    apriltag_detections_destroy(dets);
  }
  state.counters["detections"] = found;
  apriltag_detector_destroy(td);
  tag36h11_destroy(tf);
}

void BM_Aruco(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_APRILTAG_36h11);
  auto params = cv::aruco::DetectorParameters::create();
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_APRILTAG;
  const cv::Mat& img = scene(w, h);
  std::size_t found = 0;
  for (auto _ : state) {
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(img, dict, corners, ids, params);
    found = ids.size();
  }
  state.counters["detections"] = static_cast<double>(found);
}

void Resolutions(benchmark::internal::Benchmark* b, std::vector<long> modes) {
  for (const auto& [w, h] : {std::pair{640, 480}, std::pair{1280, 720}, std::pair{1920, 1080}})
    for (const long m : modes) b->Args({w, h, m});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

// mode 0: full resolution, 1: half resolution, 2: full resolution with the 2012 code's close-enough rule.
BENCHMARK(BM_Ours)->Apply([](auto* b) { Resolutions(b, {0, 1, 2}); })->ArgNames({"w", "h", "mode"});
BENCHMARK(BM_AprilTag3)->Apply([](auto* b) { Resolutions(b, {1, 2}); })->ArgNames({"w", "h", "decimate"});
BENCHMARK(BM_Aruco)->Apply([](auto* b) { Resolutions(b, {0}); })->ArgNames({"w", "h", "refine_apriltag"});

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // every detector single-threaded, for a fair comparison
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
