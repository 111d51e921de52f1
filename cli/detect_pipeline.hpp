#pragma once
// tagbench detect: processing one input (detect, explain, pictures) and the ordered parallel
// pipeline that runs it over every input: the main thread reads inputs (and video frames) into
// jobs, workers detect, the main thread prints outcomes in input order through the Sink.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cli/detect_args.hpp"
#include "cli/detect_inputs.hpp"
#include "cli/detect_output.hpp"
#include "detect/detector.hpp"
#include "tools/progress.hpp"

namespace tagbench::cli::detect_cmd {

// One input: its detections, the --explain answers and the pictures (--draw, --debug-dir).
class Processor {
 public:
  Processor(const Settings& s, const Detector& det) : s_(s), det_(det) {}

  // `ws`: the calling worker's own buffers, so a stream of frames of one size allocates them once.
  // Never throws: a failure is the outcome's error, and the pictures it had written are removed.
  Outcome run(Job& job, DetectorWorkspace& ws) const;

  // After the run: the directories it created that hold nothing (their inputs failed, e.g. on a full
  // disk) are removed, deepest first. Not done on a failure: another worker may be about to write there.
  void remove_empty_created_dirs() const;

 private:
  static void fail(Outcome& o, const std::vector<std::filesystem::path>& written, const std::string& why);
  // Output directories are created on first use (so a run whose inputs all fail creates nothing).
  void make_parent(const std::filesystem::path& file) const;

  const Settings& s_;
  const Detector& det_;
  mutable std::mutex dir_mutex_;
  mutable std::vector<std::filesystem::path> created_dirs_;  // by make_parent, for remove_empty_created_dirs
};

// The ordered parallel pipeline. At most `window` (2 x threads + 2) jobs are in flight; progress on
// stderr when it is a terminal.
class Pipeline {
 public:
  Pipeline(const Processor& proc, Sink& sink, int threads);
  ~Pipeline() { stop(); }
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  void add_expected(std::size_t n) { expected_ += n; }
  void submit(Job job);
  // Every job submitted emitted, the workers joined.
  void finish();

 private:
  void emit_next();
  void work();
  void stop();

  const Processor& proc_;
  Sink& sink_;
  std::size_t window_;
  ProgressBar bar_;
  std::chrono::steady_clock::time_point start_;
  std::size_t submitted_ = 0, emitted_ = 0, expected_ = 0;
  std::mutex m_;
  std::condition_variable work_cv_, done_cv_;
  std::deque<Job> queue_;
  std::map<std::size_t, Outcome> done_;
  bool closing_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace tagbench::cli::detect_cmd
