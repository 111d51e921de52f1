#include "margin_tradeoff.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "codes/families.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRangeRate = 0.9;  // range_m: every step up to it detected in at least this share of frames

// One true-side frame of the scored detector.
struct TrueFrame {
  std::string part, unit;
  double step = 0, black_square_px = 0, margin = kNaN;
  bool detected = false;
};

std::vector<TrueFrame> true_frames(const SweepResult& r) {
  std::vector<TrueFrame> out;
  for (const SweepRow& row : r.rows) {
    if (row.detector != kMarginDetector) continue;
    const SweepFrame& f = r.frames[row.frame];
    TrueFrame t;
    switch (r.settings.experiment) {
      case Experiment::kAngle: t.part = "angle", t.unit = "deg"; break;
      case Experiment::kDistance: t.part = "distance", t.unit = "m"; break;
      case Experiment::kSixdof: t.part = "sixdof", t.unit = "none"; break;
      case Experiment::kConditions:
        t.part = condition_name(f.condition);
        t.unit = condition_info(f.condition).unit;
        break;
    }
    t.step = f.step;
    t.black_square_px = f.truth.black_square_px;
    t.detected = row.detected_right_id;
    t.margin = row.decision_margin;
    out.push_back(std::move(t));
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::vector<double> default_margin_thresholds() {
  std::vector<double> t;
  for (int i = 0; i < 20; ++i) t.push_back(i * 0.05);
  return t;
}

void check_margin_thresholds(const std::vector<double>& thresholds) {
  if (thresholds.empty()) throw std::invalid_argument("no threshold given");
  for (std::size_t i = 0; i < thresholds.size(); ++i) {
    if (!(thresholds[i] >= 0 && thresholds[i] <= 1))
      throw std::invalid_argument("the threshold " + format_number(thresholds[i], "%.6g") + " is outside 0..1");
    if (i && !(thresholds[i] > thresholds[i - 1]))
      throw std::invalid_argument("the thresholds must be ascending without repeats");
  }
}

MarginTradeoff margin_tradeoff(const FpDetectorsRun& fp, const std::vector<MarginFamilySweeps>& sweeps,
                               const std::vector<double>& thresholds) {
  check_margin_thresholds(thresholds);
  const auto& ran = fp.options;
  const bool have_detector =
      std::find(ran.detectors.begin(), ran.detectors.end(), kMarginDetector) != ran.detectors.end();

  // The corpus images that count (readable), and their megapixels.
  std::uint64_t images = 0;
  double megapixels = 0;
  for (const auto& im : fp.images)
    if (im.status == "ok") {
      ++images;
      megapixels += static_cast<double>(im.width) * im.height / 1e6;
    }

  // A step of a part of the true side: its frames' margins (NaN: not detected) and black-square widths.
  struct Step {
    std::string unit;
    std::vector<double> margins, widths;
  };
  MarginTradeoff out;
  for (const MarginFamilySweeps& fs : sweeps) {
    if (!have_detector || std::find(ran.families.begin(), ran.families.end(), fs.family) == ran.families.end())
      throw std::invalid_argument("family " + fs.family + ": no corpus run of " + kMarginDetector);
    // Grouped once: part (in the sweeps' order) -> step (ascending) -> frames.
    std::vector<std::pair<std::string, std::map<double, Step>>> parts;
    for (const SweepResult& r : fs.sweeps) {
      if (canonical_family_name(r.settings.family) != canonical_family_name(fs.family))
        throw std::invalid_argument("a " + r.settings.family + " sweep given for family " + fs.family);
      const auto& d = r.settings.detectors;
      if (std::find(d.begin(), d.end(), kMarginDetector) == d.end())
        throw std::invalid_argument(std::string("a sweep without ") + kMarginDetector);
      for (const TrueFrame& t : true_frames(r)) {
        auto it = std::find_if(parts.begin(), parts.end(), [&](const auto& p) { return p.first == t.part; });
        if (it == parts.end()) it = parts.insert(parts.end(), {t.part, {}});
        Step& st = it->second[t.step];
        st.unit = t.unit;
        st.margins.push_back(t.detected ? t.margin : kNaN);
        st.widths.push_back(t.black_square_px);
      }
    }
    // False detections of this family, their margins; and which images they are in.
    std::vector<std::pair<double, std::uint32_t>> false_margins;
    for (const auto& d : fp.detections)
      if (d.detector == kMarginDetector && d.family == fs.family && fp.images[d.image].status == "ok")
        false_margins.emplace_back(d.decision_margin, d.image);

    for (const double m : thresholds) {
      MarginSummaryRow s;
      s.family = fs.family;
      s.threshold = m;
      s.images = images;
      s.megapixels = megapixels;
      std::set<std::uint32_t> with;
      for (const auto& [margin, image] : false_margins)
        if (margin >= m) {
          ++s.false_detections;
          with.insert(image);
        }
      s.images_with_false = with.size();
      if (images > 0) {
        s.fp_per_image = static_cast<double>(s.false_detections) / static_cast<double>(images);
        s.image_share = static_cast<double>(s.images_with_false) / static_cast<double>(images);
        s.fp_per_image_ci = poisson_interval(s.false_detections, static_cast<double>(images));
      }
      s.image_share_ci = wilson_interval(s.images_with_false, images);

      for (const auto& [part, steps] : parts) {
        MarginPartStats p;
        p.part = part;
        p.range_m = part == "distance" ? 0.0 : kNaN;
        bool in_range = true;
        for (const auto& [step, frames] : steps) {
          MarginStepRow st;
          st.family = fs.family;
          st.threshold = m;
          st.part = part;
          st.step_unit = frames.unit;
          st.step = step;
          st.frames = frames.margins.size();
          st.detected = static_cast<std::uint64_t>(
              std::count_if(frames.margins.begin(), frames.margins.end(), [&](double x) { return x >= m; }));
          st.rate = static_cast<double>(st.detected) / static_cast<double>(st.frames);
          st.rate_ci = wilson_interval(st.detected, st.frames);
          st.black_square_px_median = median(frames.widths);
          p.frames += st.frames;
          p.detected += st.detected;
          if (part == "distance" && in_range) {
            if (st.rate >= kRangeRate) p.range_m = step;
            else in_range = false;
          }
          out.steps.push_back(std::move(st));
        }
        p.rate = p.frames ? static_cast<double>(p.detected) / static_cast<double>(p.frames) : 0;
        p.rate_ci = wilson_interval(p.detected, p.frames);
        s.parts.push_back(std::move(p));
      }
      out.summary.push_back(std::move(s));
    }
  }
  return out;
}

std::string margin_summary_csv(const MarginTradeoff& t) {
  std::ostringstream o;
  o << "family,detector,threshold,images,megapixels,false_detections,fp_per_image,fp_per_image_ci95_lo,"
       "fp_per_image_ci95_hi,images_with_false,image_share,image_share_ci95_lo,image_share_ci95_hi";
  std::vector<std::string> parts;
  if (!t.summary.empty())
    for (const auto& p : t.summary.front().parts) parts.push_back(p.part);
  for (const auto& p : parts)
    for (const char* column : {"_frames", "_detected", "_rate", "_rate_ci95_lo", "_rate_ci95_hi"}) o << ',' << p << column;
  const bool distance = std::find(parts.begin(), parts.end(), "distance") != parts.end();
  if (distance) o << ",distance_range_m";
  o << '\n';
  for (const auto& s : t.summary) {
    if (s.parts.size() != parts.size()) throw std::invalid_argument("families with different sweeps in one table");
    o << csv_field(s.family) << ',' << kMarginDetector << ',' << format_cell(s.threshold, "%.4g") << ',' << s.images << ','
      << format_cell(s.megapixels, "%.6g") << ',' << s.false_detections << ',' << format_cell(s.fp_per_image, "%.6g")
      << ',' << format_cell(s.fp_per_image_ci.lo, "%.6g") << ',' << format_cell(s.fp_per_image_ci.hi, "%.6g") << ','
      << s.images_with_false << ',' << format_cell(s.image_share, "%.6g") << ','
      << format_cell(s.image_share_ci.lo, "%.6g") << ',' << format_cell(s.image_share_ci.hi, "%.6g");
    double range = kNaN;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const auto& p = s.parts[i];
      if (p.part != parts[i]) throw std::invalid_argument("families with different sweeps in one table");
      o << ',' << p.frames << ',' << p.detected << ',' << format_cell(p.rate, "%.6g") << ','
        << format_cell(p.rate_ci.lo, "%.6g") << ',' << format_cell(p.rate_ci.hi, "%.6g");
      if (p.part == "distance") range = p.range_m;
    }
    if (distance) o << ',' << format_cell(range, "%.6g");
    o << '\n';
  }
  return o.str();
}

std::string margin_steps_csv(const MarginTradeoff& t) {
  std::ostringstream o;
  o << "family,detector,threshold,part,step,step_unit,frames,detected,rate,rate_ci95_lo,rate_ci95_hi,"
       "black_square_px_median\n";
  for (const auto& s : t.steps)
    o << csv_field(s.family) << ',' << kMarginDetector << ',' << format_cell(s.threshold, "%.4g") << ',' << s.part << ','
      << format_cell(s.step, "%.6g") << ',' << s.step_unit << ',' << s.frames << ',' << s.detected << ','
      << format_cell(s.rate, "%.6g") << ',' << format_cell(s.rate_ci.lo, "%.6g") << ','
      << format_cell(s.rate_ci.hi, "%.6g") << ',' << format_cell(s.black_square_px_median, "%.4f") << '\n';
  return o.str();
}

}  // namespace tagbench::bench
