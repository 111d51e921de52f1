// Per (condition, step, detector) summaries of a sweep's rows.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "raytrace/sweep_detail.hpp"
#include "raytrace/sweeps.hpp"
#include "stats.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

double quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::vector<SummaryRow> summarize(const SweepResult& r) {
  struct Acc {
    SummaryRow row;
    std::vector<double> o, dm, dp, c, px, ms;
  };
  std::vector<Acc> groups;
  std::map<std::tuple<int, double, std::string>, std::size_t> index;
  for (const SweepRow& row : r.rows) {
    const SweepFrame& f = r.frames[row.frame];
    const auto key = std::make_tuple(static_cast<int>(f.condition), f.step, row.detector);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, groups.size()).first;
      Acc a;
      a.row.condition = f.condition;
      a.row.step = f.step;
      a.row.detector = row.detector;
      for (std::size_t k = 0; k < r.settings.detectors.size() && k < r.can_explain.size(); ++k)
        if (r.settings.detectors[k] == row.detector) a.row.lost.explains = r.can_explain[k];
      groups.push_back(std::move(a));
    }
    Acc& a = groups[it->second];
    ++a.row.frames;
    a.px.push_back(f.truth.black_square_px);
    a.ms.push_back(row.ms);
    if (row.wrong_id) ++a.row.wrong_id_frames;
    a.row.lost.add(row.loss);
    if (!row.detected_right_id) continue;
    ++a.row.detected;
    a.o.push_back(row.orientation_error_deg);
    a.dm.push_back(row.distance_error_m);
    a.dp.push_back(row.distance_error_percent);
    a.c.push_back(row.corner_rms_px);
  }
  std::vector<SummaryRow> out;
  const auto stats = [](const std::vector<double>& v) { return ErrorStats{quantile(v, 0.5), quantile(v, 0.1), quantile(v, 0.9)}; };
  for (Acc& a : groups) {
    SummaryRow& s = a.row;
    s.detection_rate = static_cast<double>(s.detected) / s.frames;
    const Interval ci = wilson_interval(static_cast<std::uint64_t>(s.detected), static_cast<std::uint64_t>(s.frames));
    s.rate_lo95 = ci.lo;
    s.rate_hi95 = ci.hi;
    s.black_square_px_median = quantile(a.px, 0.5);
    s.ms_median = quantile(a.ms, 0.5);
    s.orientation_deg = stats(a.o);
    s.distance_m = stats(a.dm);
    s.distance_percent = stats(a.dp);
    s.corner_rms_px = stats(a.c);
    out.push_back(s);
  }
  return out;
}

}  // namespace tagbench::bench
