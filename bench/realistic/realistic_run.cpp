// The detectors on the realistic set (realistic_run.hpp): running and scoring.
#include "realistic/realistic_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "detect/homography.hpp"
#include "stats.hpp"
#include "raytrace/comparators.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double quad_size(const Corners& c) { return std::sqrt(std::abs(twice_signed_area(c)) / 2); }

double corner_rms(const Corners& a, const Corners& b) {
  double s = 0;
  for (std::size_t i = 0; i < 4; ++i) s += (a[i] - b[i]).squaredNorm();
  return std::sqrt(s / 4);
}

bool inside(const Corners& q, const Eigen::Vector2d& p) {  // convex quad, either winding
  int pos = 0, neg = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d e = q[(i + 1) % 4] - q[i], r = p - q[i];
    const double c = e.x() * r.y() - e.y() * r.x();
    (c >= 0 ? pos : neg)++;
  }
  return pos == 4 || neg == 4;
}

Eigen::Vector2d centre(const Corners& c) { return (c[0] + c[1] + c[2] + c[3]) / 4; }

}  // namespace

const std::vector<SizeBin>& size_bins() {
  static const std::vector<SizeBin> bins = {{"<12", 0, 12},    {"12-16", 12, 16}, {"16-20", 16, 20},
                                            {"20-24", 20, 24}, {"24-28", 24, 28}, {"28-32", 28, 32},
                                            {"32-40", 32, 40}, {">40", 40, std::numeric_limits<double>::infinity()}};
  return bins;
}

const SizeBin& size_bin_of(double px) {
  const auto& b = size_bins();
  for (std::size_t i = 1; i + 1 < b.size(); ++i)
    if (px >= b[i].lo && (px < b[i].hi || (i + 2 == b.size() && px <= b[i].hi))) return b[i];  // 40 itself is in 32-40
  return px < b[1].lo ? b.front() : b.back();
}

std::vector<TagMatch> match_tags(std::span<const RealisticTag> tags, std::span<const Found> found) {
  std::vector<TagMatch> m(tags.size());
  std::vector<bool> used(found.size(), false);
  for (std::size_t t = 0; t < tags.size(); ++t) {
    const RealisticTag& tag = tags[t];
    int best = -1;
    double best_err = std::max(2.0, 0.2 * tag.black_square_px);
    for (std::size_t k = 0; k < found.size(); ++k) {
      const Found& x = found[k];
      if (used[k] || x.id != tag.id || canonical_family_name(x.family) != canonical_family_name(tag.family)) continue;
      const double e = corner_rms(x.corners, tag.corners);
      if (e <= best_err) best = static_cast<int>(k), best_err = e;
    }
    if (best >= 0) used[static_cast<std::size_t>(best)] = true, m[t] = {best, best_err};
  }
  return m;
}

RealisticRunSettings resolve_run_settings(const RealisticRunSettings& in) {
  RealisticRunSettings s = in;
  check_settings(s.set);
  if (s.frames <= 0) throw std::invalid_argument("frames must be > 0 (got " + std::to_string(s.frames) + ")");
  if (s.detectors.empty()) {  // the sweeps' seven and the thorough profile after the default
    s.detectors = comparator_names();
    s.detectors.insert(s.detectors.begin() + 1, "tagbench-thorough");
  }
  const auto& known = known_comparator_names();
  for (std::size_t i = 0; i < s.detectors.size(); ++i) {
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    if (std::find(known.begin(), known.end(), s.detectors[i]) == known.end() && !is_ours_variant(s.detectors[i]))
      throw std::invalid_argument("unknown detector '" + s.detectors[i] + "' (" + list + ")");
    if (std::find(s.detectors.begin(), s.detectors.begin() + static_cast<std::ptrdiff_t>(i), s.detectors[i]) !=
        s.detectors.begin() + static_cast<std::ptrdiff_t>(i))
      throw std::invalid_argument("detector '" + s.detectors[i] + "' given twice");
  }
  return s;
}

RealisticResult run_realistic(const RealisticRunSettings& settings, const std::function<void(const RealisticFrame&)>& on_frame,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  RealisticResult r;
  r.settings = resolve_run_settings(settings);
  const RealisticRunSettings& s = r.settings;
  ComparatorSetup setup;
  setup.family = s.set.family;
  // Our detectors are told the camera's encoding gamma, as a user would set it for their camera (a
  // variant's input_gamma overrides it); ideal frames are not gamma-encoded.
  setup.input_gamma = s.set.degrade ? s.set.gamma : 1.0;
  std::vector<std::unique_ptr<Comparator>> dets;
  for (const auto& name : s.detectors) dets.push_back(make_comparator(name, setup));  // throws for a family it lacks
  for (const auto& det : dets) r.can_explain.push_back(det->can_explain());
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);  // one thread per detector, as in the sweeps (aruco uses OpenCV's pool)
  struct Restore {
    int n;
    ~Restore() { cv::setNumThreads(n); }
  } restore{threads};
  using Clock = std::chrono::steady_clock;
  for (int i = 0; i < s.frames; ++i) {
    const auto t0 = Clock::now();
    const RealisticFrame f = make_realistic_frame(s.set, i);
    const auto t1 = Clock::now();
    r.generate_seconds += std::chrono::duration<double>(t1 - t0).count();
    if (on_frame) on_frame(f);
    const std::size_t fi = r.frames.size();
    r.frames.push_back({f.index, f.frame_seed, f.image.cols, f.image.rows, f.camera, f.degradation, f.tags});
    const auto t2 = Clock::now();
    const std::size_t frame_first = r.scores.size();  // then detector-major: frame_first + d * tags + t
    for (std::size_t d = 0; d < dets.size(); ++d) {
      const DetectorOutput out = dets[d]->run(f.image);
      const std::vector<TagMatch> matches = match_tags(f.tags, out.found);
      std::vector<bool> used(out.found.size(), false);
      const std::size_t first = r.scores.size();
      for (std::size_t t = 0; t < f.tags.size(); ++t) {
        TagScore sc{fi, t, s.detectors[d], false, false, kNaN, kNaN, out.ms, std::nullopt};
        if (const int k = matches[t].found; k >= 0) {
          used[static_cast<std::size_t>(k)] = true;
          sc.detected = true;
          sc.corner_rms_px = matches[t].corner_rms_px;
          sc.decision_margin = out.found[static_cast<std::size_t>(k)].decision_margin;
        }
        r.scores.push_back(sc);
      }
      for (std::size_t k = 0; k < out.found.size(); ++k) {
        if (used[k]) continue;
        const Found& x = out.found[k];
        RealisticFalseDetection fd{fi, s.detectors[d], x.family, x.id, quad_size(x.corners), centre(x.corners), -1};
        for (std::size_t t = 0; t < f.tags.size(); ++t)
          if (inside(f.tags[t].corners, fd.centre)) {
            fd.at_tag = static_cast<int>(t);
            r.scores[first + t].wrong_id = true;
          }
        r.false_detections.push_back(std::move(fd));
      }
    }
    r.detect_seconds += std::chrono::duration<double>(Clock::now() - t2).count();
    // Where each missed tag was lost, for the detectors that can say: detected again with a trace, untimed.
    for (std::size_t d = 0; d < dets.size(); ++d)
      for (std::size_t t = 0; t < f.tags.size(); ++t) {
        TagScore& sc = r.scores[frame_first + d * f.tags.size() + t];
        if (!sc.detected) sc.loss = dets[d]->explain(f.image, f.tags[t].family, f.tags[t].id, f.tags[t].corners);
      }
    if (progress) progress(static_cast<std::size_t>(i + 1), static_cast<std::size_t>(s.frames));
  }
  // Tag-major order within a frame reads better: frame, tag, detector.
  std::stable_sort(r.scores.begin(), r.scores.end(), [](const TagScore& a, const TagScore& b) {
    return a.frame != b.frame ? a.frame < b.frame : a.tag < b.tag;
  });
  return r;
}

std::vector<RealisticSummaryRow> summarize_realistic(const RealisticResult& r) {
  const auto& dets = r.settings.detectors;
  struct Acc {
    RealisticSummaryRow row;
    std::vector<double> err;
  };
  std::vector<std::string> bins;
  for (const auto& b : size_bins()) bins.push_back(b.name);
  bins.push_back("all");
  std::map<std::pair<std::string, std::string>, Acc> acc;
  const auto slot = [&](const std::string& bin, const std::string& det) -> Acc& { return acc[{bin, det}]; };
  for (const TagScore& sc : r.scores) {
    const double px = r.frames[sc.frame].tags[sc.tag].black_square_px;
    for (const std::string& bin : {size_bin_of(px).name, std::string("all")}) {
      Acc& a = slot(bin, sc.detector);
      ++a.row.tags;
      if (sc.wrong_id) ++a.row.wrong_id_tags;
      a.row.lost.add(sc.loss);
      if (!sc.detected) continue;
      ++a.row.detected;
      a.err.push_back(sc.corner_rms_px);
    }
  }
  for (const RealisticFalseDetection& fd : r.false_detections)
    for (const std::string& bin : {size_bin_of(fd.size_px).name, std::string("all")}) ++slot(bin, fd.detector).row.false_detections;
  std::vector<RealisticSummaryRow> out;
  for (std::size_t bi = 0; bi < bins.size(); ++bi) {
    bool any = false;
    for (const auto& d : dets) any = any || acc.count({bins[bi], d});
    if (!any) continue;
    for (const auto& d : dets) {
      Acc& a = slot(bins[bi], d);
      RealisticSummaryRow row = a.row;
      row.bin = bins[bi];
      row.detector = d;
      for (std::size_t k = 0; k < dets.size() && k < r.can_explain.size(); ++k)
        if (dets[k] == d) row.lost.explains = r.can_explain[k];
      if (bi < size_bins().size()) {
        row.bin_lo = size_bins()[bi].lo;
        row.bin_hi = size_bins()[bi].hi;
      } else {
        row.bin_lo = row.bin_hi = kNaN;
      }
      row.rate = row.tags ? static_cast<double>(row.detected) / row.tags : kNaN;
      const Interval ci = wilson_interval(static_cast<std::uint64_t>(row.detected), static_cast<std::uint64_t>(row.tags));
      row.rate_lo95 = row.tags ? ci.lo : kNaN;
      row.rate_hi95 = row.tags ? ci.hi : kNaN;
      row.corner_rms_px_median = quantile(a.err, 0.5);
      row.corner_rms_px_p90 = quantile(a.err, 0.9);
      out.push_back(row);
    }
  }
  return out;
}

}  // namespace tagbench::bench
