#include "detect/border_kink.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/payload_decode.hpp"  // sample_bilinear

namespace tagbench {
namespace {

struct Scan {
  double offset, sigma;
};

// The steps of one scan: offsets t along the normal; the samples are taken at t + h and t - h.
struct ScanSteps {
  std::vector<double> t;
  std::size_t m = 0;              // 2 h / step: the sample at t - h of step j may be the one at t + h of step j - m
  double lo_end = 0, hi_end = 0;  // the smallest and largest offset sampled
  double centre = NAN, range = NAN;  // what they were made for (NaN: nothing yet)
};

// Buffers of the scans, kept from scan to scan (storage only grows): the steps of centre 0 (every
// point's first scan on a side, one range) are made once per side, those of the re-centred scans each time.
struct ScanScratch {
  ScanSteps at_zero, recentred;
  std::vector<float> value;  // the sample at t + h of each offset
};

const ScanSteps& scan_steps(double centre, double range, const BorderKinkOptions& opt, ScanScratch& scratch) {
  ScanSteps& s = centre == 0 ? scratch.at_zero : scratch.recentred;
  if (s.centre == centre && s.range == range) return s;
  const double h = opt.derivative_half_px;
  s.t.clear();
  for (double t = centre - range; t <= centre + range + 1e-9; t += opt.step_px) s.t.push_back(t);
  s.m = static_cast<std::size_t>(std::max(0L, std::lround(2 * h / opt.step_px)));
  // t only grows (t += step, step > 0), and so, rounded, do t - h and t + h: the first step holds the
  // smallest offset sampled and the last the largest (the same doubles as a min/max over every step).
  double lo_end = HUGE_VAL, hi_end = -HUGE_VAL;
  if (!s.t.empty()) {
    lo_end = std::min(s.t.front() - h, s.t.front() + h);
    hi_end = std::max(s.t.back() - h, s.t.back() + h);
  }
  s.lo_end = lo_end, s.hi_end = hi_end, s.centre = centre, s.range = range;
  return s;
}

// The edge along p + t n for t in centre +- range: weighted mean and spread of the squared positive
// derivative; nullopt when a sample leaves the image or no step rises.
// Speed, the result unchanged: the sample at t - h of step j is the one at t + h of step j - m
// (m = 2 h / step) when the two offsets are equal as doubles (they are wherever the steps add
// exactly), so it is reused, not taken again; and p + u n is monotone in u coordinate by coordinate
// (in floating point too), so the scan's two end samples say whether every sample is inside the image.
std::optional<Scan> scan_edge(const ImageF& img, const Eigen::Vector2d& p, const Eigen::Vector2d& n, double centre,
                              double range, const BorderKinkOptions& opt, ScanScratch& scratch) {
  const double h = opt.derivative_half_px;
  const ScanSteps& steps = scan_steps(centre, range, opt, scratch);
  const std::size_t ns = steps.t.size();
  if (ns == 0) return std::nullopt;
  const auto inside = [&](const Eigen::Vector2d& q) {  // sample_bilinear's domain
    return q.x() >= 0 && q.y() >= 0 && q.x() <= img.width - 1 && q.y() <= img.height - 1;
  };
  if (img.empty() || !inside(p + steps.lo_end * n) || !inside(p + steps.hi_end * n)) return std::nullopt;
  scratch.value.resize(ns);
  float* value = scratch.value.data();
  const double* ts = steps.t.data();
  const std::size_t m = steps.m;
  // The samples at t + h and at t - h each step a quarter pixel along the scan: each keeps its 2 x 2
  // pixels (BilinearCell: the same value, the pixels read again only when the cell changes).
  BilinearCell cell_hi, cell_lo;
  double sw = 0, st = 0, stt = 0;
  for (std::size_t j = 0; j < ns; ++j) {
    const double t = ts[j];
    const float hi = value[j] = sample_bilinear_inside(img, p + (t + h) * n, cell_hi);
    const float lo = m >= 1 && j >= m && ts[j - m] + h == t - h ? value[j - m]
                                                                 : sample_bilinear_inside(img, p + (t - h) * n, cell_lo);
    const double g = hi - lo;
    if (g <= 0) continue;
    sw += g * g, st += g * g * t, stt += g * g * t * t;
  }
  if (!(sw > 0)) return std::nullopt;
  const double mean = st / sw, var = std::max(0.0, stt / sw - mean * mean);
  // g is the step's Gaussian (sigma) widened by the difference's box (variance h^2 / 3); g^2 has half its variance.
  return Scan{mean, std::sqrt(std::max(0.0, 2 * var - h * h / 3))};
}

}  // namespace

std::optional<BrokenLine> fit_broken_line(std::span<const Eigen::Vector2d> pts, double max_s0) {
  std::optional<BrokenLine> best;
  const int steps = std::max(0, static_cast<int>(std::lround(max_s0 / 0.025)));
  for (int k = -steps; k <= steps; ++k) {
    const double s0 = k * 0.025;
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    for (const auto& q : pts) {
      const Eigen::Vector3d r(1, q.x(), std::abs(q.x() - s0));
      AtA += r * r.transpose();
      Atb += r * q.y();
    }
    const Eigen::Vector3d x = AtA.ldlt().solve(Atb);
    if (!x.allFinite()) continue;
    double ssr = 0;
    for (const auto& q : pts) {
      const double e = q.y() - (x(0) + x(1) * q.x() + x(2) * std::abs(q.x() - s0));
      ssr += e * e;
    }
    if (!best || ssr < best->ssr) best = BrokenLine{x(0), x(1), x(2), s0, ssr, AtA.inverse()(2, 2)};
  }
  return best;
}

std::optional<std::array<SideKink, 4>> measure_border_kinks(const ImageF& img, const Corners& corners,
                                                            const BorderKinkOptions& opt) {
  if (img.empty() || opt.cells_across < 1 || opt.samples < 4 || !(opt.step_px > 0)) return std::nullopt;
  const auto H = tag_homography(corners);
  if (!H) return std::nullopt;
  const Corners& tag = tag_square_corners();
  const Eigen::Vector2d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  std::array<SideKink, 4> out;
  std::vector<Eigen::Vector2d> pts;
  std::vector<double> blur;
  ScanScratch scan;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % 4];
    const double len = (b - a).norm();
    if (!(len > 1e-6)) continue;
    Eigen::Vector2d n((b - a).y() / len, -(b - a).x() / len);
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    const double range = std::max(opt.min_range_px, opt.range_cells * len / opt.cells_across);
    const auto on_side = [&](double s) {  // the flat homography's point at tag parameter s of side i
      return apply_homography(*H, tag[i] + 0.5 * (s + 1) * (tag[(i + 1) % 4] - tag[i]));
    };
    pts.clear();
    blur.clear();
    for (int k = 0; k < opt.samples; ++k) {
      const double s = -1 + opt.end_margin + (2 - 2 * opt.end_margin) * (k + 0.5) / opt.samples;
      const Eigen::Vector2d p = on_side(s);
      auto e = scan_edge(img, p, n, 0, range, opt, scan);
      if (e) e = scan_edge(img, p, n, e->offset, range, opt, scan);  // re-centred: an edge near the reach is not pulled in
      if (!e) continue;
      pts.emplace_back(s, e->offset);
      blur.push_back(e->sigma);
    }
    if (2 * static_cast<int>(pts.size()) < opt.samples) continue;
    const auto f = fit_broken_line(pts, opt.max_fold_offset);
    if (!f) continue;
    SideKink& k = out[i];
    k.valid = true;
    k.kink_px = f->c;
    k.fold_s = f->s0;
    k.rms_px = std::sqrt(f->ssr / static_cast<double>(pts.size()));
    // Standard error of c from the residual (3 parameters fitted; at least 2 points: samples >= 4).
    k.kink_se_px = std::sqrt(f->ssr / std::max(1.0, static_cast<double>(pts.size()) - 3) * std::max(0.0, f->c_var));
    const auto o = [&](double s) { return f->a + f->b * s + f->c * std::abs(s - f->s0); };
    k.fold_point = on_side(f->s0) + o(f->s0) * n;
    k.ends = {on_side(-1) + o(-1) * n, on_side(1) + o(1) * n};
    std::nth_element(blur.begin(), blur.begin() + static_cast<std::ptrdiff_t>(blur.size() / 2), blur.end());
    k.blur_px = blur[blur.size() / 2];
  }
  return out;
}

double max_kink_px(const std::array<SideKink, 4>& sides) {
  double m = 0;
  for (const SideKink& s : sides)
    if (s.valid) m = std::max(m, std::abs(s.kink_px));
  return m;
}

double max_kink_significance(const std::array<SideKink, 4>& sides) {
  double m = 0;
  for (const SideKink& s : sides)
    if (s.valid) m = std::max(m, std::abs(s.kink_px) / std::max(s.kink_se_px, 1e-9));
  return m;
}

double median_blur_px(const std::array<SideKink, 4>& sides) {
  std::vector<double> b;
  for (const SideKink& s : sides)
    if (s.valid) b.push_back(s.blur_px);
  if (b.empty()) return 0;
  std::sort(b.begin(), b.end());
  return b.size() % 2 ? b[b.size() / 2] : 0.5 * (b[b.size() / 2 - 1] + b[b.size() / 2]);
}

}  // namespace tagbench
