#include "tools/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace tagbench {

// On a terminal the bar shows at once; in a log the first line comes after a minute, so a short run
// (or one that fails early) prints nothing but its result or its one-line error.
ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(::isatty(STDERR_FILENO) != 0),
      last_(std::chrono::steady_clock::now() - (tty_ ? std::chrono::hours(1) : std::chrono::hours(0))) {}

ProgressBar::~ProgressBar() {
  if (drawn_ && tty_) std::fputc('\n', stderr);
}

std::string ProgressBar::format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  char buf[32];
  const long long t = static_cast<long long>(s + 0.5);
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%lldh%02lldm", t / 3600, t / 60 % 60);
  else if (t >= 60) std::snprintf(buf, sizeof buf, "%lldm%02llds", t / 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%llds", t);
  return buf;
}

void ProgressBar::update(double fraction, const std::string& count, const std::string& detail, double eta) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const auto min_gap = tty_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(60000);
  if (now - last_ < min_gap && (fraction < 1.0 || (!tty_ && !drawn_))) return;
  last_ = now;
  fraction = std::fmin(1.0, std::fmax(0.0, fraction));
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %5.1f%% %s %s, left %s\033[K", label_.c_str(), bar.c_str(), 100 * fraction,
                 count.c_str(), detail.c_str(), format_duration(eta).c_str());
  } else {
    std::fprintf(stderr, "%s: %.3f%% %s %s, left %s\n", label_.c_str(), 100 * fraction, count.c_str(),
                 detail.c_str(), format_duration(eta).c_str());
  }
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace tagbench
