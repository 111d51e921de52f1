// Per (condition, step, detector) summaries of a sweep's rows.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "raytrace/sixdof.hpp"
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
  // The group's key: (condition, step, detector); sixdof: (variable, bin, detector) as (-1 - variable, bin).
  std::map<std::tuple<int, double, std::string>, std::size_t> index;
  const bool sixdof = r.settings.experiment == Experiment::kSixdof;
  const std::vector<SixdofVariable> vars = sixdof ? sixdof_variables(r.settings) : std::vector<SixdofVariable>{};
  const int bins = r.settings.sixdof.bins;
  // Where a row counts: one group for the step sweeps; sixdof: "all", then one bin of every variable.
  struct Group {
    std::tuple<int, double, std::string> key;
    SummaryRow row;
  };
  const auto groups_of = [&](const SweepFrame& f, const std::string& detector) {
    std::vector<Group> out;
    if (!sixdof) {
      SummaryRow s;
      s.condition = f.condition;
      s.step = f.step;
      s.detector = detector;
      out.push_back({std::make_tuple(static_cast<int>(f.condition), f.step, detector), s});
      return out;
    }
    SummaryRow all;
    all.variable = "all";
    all.detector = detector;
    out.push_back({std::make_tuple(-1000, 0.0, detector), all});
    for (std::size_t v = 0; v < vars.size(); ++v) {
      const double width = (vars[v].hi - vars[v].lo) / bins;
      const int b = width > 0 ? std::clamp(static_cast<int>(std::floor((sixdof_value(f, v) - vars[v].lo) / width)), 0, bins - 1) : 0;
      SummaryRow s;
      s.variable = vars[v].name;
      s.step = vars[v].lo + b * width;
      s.bin_hi = b == bins - 1 ? vars[v].hi : vars[v].lo + (b + 1) * width;
      s.detector = detector;
      out.push_back({std::make_tuple(-1 - static_cast<int>(v), static_cast<double>(b), detector), s});
    }
    return out;
  };
  for (const SweepRow& row : r.rows) {
    const SweepFrame& f = r.frames[row.frame];
    for (Group& g : groups_of(f, row.detector)) {
      auto it = index.find(g.key);
      if (it == index.end()) {
        it = index.emplace(g.key, groups.size()).first;
        Acc a;
        a.row = std::move(g.row);
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
  }
  if (sixdof)  // variable (in sixdof_variables' order, "all" first), bin, then the detectors' order
    std::stable_sort(groups.begin(), groups.end(), [&](const Acc& x, const Acc& y) {
      const auto rank = [&](const SummaryRow& s) {
        for (std::size_t v = 0; v < vars.size(); ++v)
          if (s.variable == vars[v].name) return static_cast<int>(v) + 1;
        return 0;
      };
      return std::make_pair(rank(x.row), x.row.step) < std::make_pair(rank(y.row), y.row.step);
    });
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
