#pragma once
// Progress for long runs, on stderr: a bar with count, rate and time left when stderr is a terminal;
// otherwise a plain line at most once a minute (so logs of background runs stay readable).
#include <chrono>
#include <string>

namespace tagbench {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();  // finishes the line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // fraction in [0,1]; `detail` is shown after the bar (e.g. "587 codes, 5.7e7 cand/s").
  void update(double fraction, const std::string& count, const std::string& detail, double eta_seconds);

  static std::string format_duration(double seconds);

 private:
  std::string label_;
  bool enabled_, tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace tagbench
