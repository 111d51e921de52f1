#include "detect/line_segments.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "detect/blur.hpp"

namespace tagbench {

namespace {

// log10 of the binomial tail sum_{i >= k} C(n, i) p^i (1 - p)^(n - i), for k > n p.
double log10_binomial_tail(int n, int k, double p) {
  if (k <= 0) return 0.0;
  if (k > n) return -1e30;
  const double lp = std::log(p), lq = std::log1p(-p);
  double term = std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * lp + (n - k) * lq;
  double sum = 1.0, ratio = 1.0;  // the tail relative to its first term
  for (int i = k + 1; i <= n; ++i) {
    ratio *= (static_cast<double>(n - i + 1) / i) * (p / (1 - p));
    sum += ratio;
    if (ratio < 1e-12 * sum) break;
  }
  return (term + std::log(sum)) / std::numbers::ln10;
}

}  // namespace

std::vector<Segment> detect_line_segments(const ImageF& img, const LineSegmentOptions& opt, LineSegmentScratch& s) {
  if (!(opt.min_gradient > 0) || !(opt.angle_tolerance_deg > 0 && opt.angle_tolerance_deg <= 90))
    throw std::invalid_argument("LineSegmentOptions: min_gradient must be > 0 and angle_tolerance_deg in (0, 90]");
  std::vector<Segment> out;
  if (img.width < 3 || img.height < 3) return out;
  gaussian_blur(img, opt.sigma, s.tmp, s.blurred);
  const ImageF& b = opt.sigma > 0 ? s.blurred : img;
  // Gradients at pixel corners: a (W - 1) x (H - 1) grid, entry (x, y) at image point (x + 0.5, y + 0.5).
  const int W = img.width - 1, H = img.height - 1;
  const std::size_t N = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  s.ux.resize(N), s.uy.resize(N), s.mag.resize(N), s.used.assign(N, 1);
  const float floor = static_cast<float>(opt.min_gradient / 255.0);
  float max_mag = 0;
  for (int y = 0; y < H; ++y) {
    const float* r0 = b.data.data() + b.index(0, y);
    const float* r1 = r0 + b.width;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(W);
    for (int x = 0; x < W; ++x) {
      const float gx = 0.5f * (r0[x + 1] + r1[x + 1] - r0[x] - r1[x]);
      const float gy = 0.5f * (r1[x] + r1[x + 1] - r0[x] - r0[x + 1]);
      const float m = std::sqrt(gx * gx + gy * gy);
      const std::size_t i = row + static_cast<std::size_t>(x);
      s.mag[i] = m;
      if (m >= floor) {
        s.used[i] = 0;
        s.ux[i] = gx / m, s.uy[i] = gy / m;
        max_mag = std::max(max_mag, m);
      }
    }
  }
  // Pseudo-order by magnitude, strongest first (LSD's bins).
  constexpr int kBins = 1024;
  s.bin_count.assign(kBins + 1, 0);
  const float to_bin = max_mag > 0 ? (kBins - 1) / max_mag : 0.0f;
  const auto bin_of = [&](std::size_t i) { return kBins - 1 - static_cast<int>(s.mag[i] * to_bin); };
  for (std::size_t i = 0; i < N; ++i)
    if (!s.used[i]) ++s.bin_count[static_cast<std::size_t>(bin_of(i)) + 1];
  for (int k = 0; k < kBins; ++k) s.bin_count[k + 1] += s.bin_count[k];
  const std::size_t candidates = s.bin_count[kBins];
  s.order.resize(candidates);
  for (std::size_t i = 0; i < N; ++i)
    if (!s.used[i]) s.order[s.bin_count[static_cast<std::size_t>(bin_of(i))]++] = static_cast<std::uint32_t>(i);

  const double tau = opt.angle_tolerance_deg * std::numbers::pi / 180;
  const float cos_tau = static_cast<float>(std::cos(tau));
  const double p = opt.angle_tolerance_deg / 180.0;
  const double log_nt = 2.5 * (std::log10(static_cast<double>(W)) + std::log10(static_cast<double>(H))) + std::log10(11.0);
  // A region of k pixels filling its rectangle exactly (n = k) is meaningful only when k log10(1/p) > log_nt.
  const int min_pixels = static_cast<int>(std::ceil((log_nt + opt.log_eps) / -std::log10(p)));
  const std::size_t max_region = opt.max_region_pixels > 0 ? static_cast<std::size_t>(opt.max_region_pixels) : N;
  const auto grow = [&](std::uint32_t seed, float cos_tol, double& sx, double& sy) {
    s.region.clear();
    s.region.push_back({static_cast<std::int32_t>(seed % static_cast<std::uint32_t>(W)), static_cast<std::int32_t>(seed / static_cast<std::uint32_t>(W)), seed});
    s.used[seed] = 1;
    sx = s.ux[seed], sy = s.uy[seed];
    float dx = s.ux[seed], dy = s.uy[seed];
    for (std::size_t r = 0; r < s.region.size() && s.region.size() <= max_region; ++r) {
      const int px = s.region[r].x, py = s.region[r].y;
      if (px == 0 || py == 0 || px == W - 1 || py == H - 1) continue;  // the grid's rim: no neighbours read
      for (int oy = -1; oy <= 1; ++oy)
        for (int ox = -1; ox <= 1; ++ox) {
          const std::size_t j = static_cast<std::size_t>(static_cast<std::int64_t>(s.region[r].i) + oy * W + ox);
          if (s.used[j] || s.ux[j] * dx + s.uy[j] * dy < cos_tol) continue;
          s.used[j] = 1;
          s.region.push_back({px + ox, py + oy, static_cast<std::uint32_t>(j)});
          sx += s.ux[j], sy += s.uy[j];
          const double inv = 1.0 / std::sqrt(sx * sx + sy * sy);  // the region's mean direction
          dx = static_cast<float>(sx * inv), dy = static_cast<float>(sy * inv);
        }
    }
  };
  struct Rect {
    double cx, cy, ex, ey, lmin, lmax, wmin, wmax;
    double length() const { return lmax - lmin + 1; }
    double width() const { return wmax - wmin + 1; }
  };
  const auto rect_of = [&](double sx, double sy) {
    Rect rc{};
    double w = 0;
    for (const auto& q : s.region) {
      const double m = s.mag[q.i];
      w += m, rc.cx += m * q.x, rc.cy += m * q.y;
    }
    rc.cx /= w, rc.cy /= w;
    double ixx = 0, iyy = 0, ixy = 0;
    for (const auto& q : s.region) {
      const double m = s.mag[q.i], x = q.x - rc.cx, y = q.y - rc.cy;
      ixx += m * x * x, iyy += m * y * y, ixy += m * x * y;
    }
    const double norm = std::sqrt(sx * sx + sy * sy), dx = sx / norm, dy = sy / norm;
    const double theta = 0.5 * std::atan2(2 * ixy, ixx - iyy);
    rc.ex = std::cos(theta), rc.ey = std::sin(theta);
    // A short region's principal axis can run along the gradient: then the edge is taken across the
    // mean gradient instead (the region's pixels are all within the tolerance of it anyway).
    if (std::abs(rc.ex * dx + rc.ey * dy) > std::sin(tau)) rc.ex = -dy, rc.ey = dx;
    // Left normal of (ex, ey) is (ey, -ex); dark is against the gradient.
    if (rc.ey * dx - rc.ex * dy > 0) rc.ex = -rc.ex, rc.ey = -rc.ey;
    rc.lmin = rc.wmin = 1e30, rc.lmax = rc.wmax = -1e30;
    for (const auto& q : s.region) {
      const double x = q.x - rc.cx, y = q.y - rc.cy;
      const double l = x * rc.ex + y * rc.ey, t = -x * rc.ey + y * rc.ex;
      rc.lmin = std::min(rc.lmin, l), rc.lmax = std::max(rc.lmax, l), rc.wmin = std::min(rc.wmin, t), rc.wmax = std::max(rc.wmax, t);
    }
    return rc;
  };
  const auto dense = [&](const Rect& rc) {
    return static_cast<double>(s.region.size()) >= opt.min_density * rc.length() * rc.width();
  };
  const float seed_floor = static_cast<float>(std::max(opt.min_seed_gradient, opt.min_gradient) / 255.0);
  for (const std::uint32_t seed : s.order) {
    if (s.mag[seed] < seed_floor) break;  // strongest first: the rest are weaker still
    if (s.used[seed]) continue;
    double sx, sy;
    grow(seed, cos_tau, sx, sy);
    if (static_cast<int>(s.region.size()) < min_pixels || s.region.size() > max_region) continue;
    Rect rc = rect_of(sx, sy);
    if (!dense(rc)) {
      // LSD's refinement: a tolerance from the spread of directions near the seed, grown again ...
      const double sxs = s.ux[seed], sys = s.uy[seed];
      const double rad2 = rc.width() * rc.width();
      const int seed_x = static_cast<int>(seed % static_cast<std::uint32_t>(W)), seed_y = static_cast<int>(seed / static_cast<std::uint32_t>(W));
      double sum = 0, sum2 = 0;
      int cnt = 0;
      for (const auto& q : s.region) {
        const double x = q.x - seed_x, y = q.y - seed_y;
        if (x * x + y * y > rad2) continue;
        const double a = std::atan2(s.ux[q.i] * sys - s.uy[q.i] * sxs, s.ux[q.i] * sxs + s.uy[q.i] * sys);
        sum += a, sum2 += a * a, ++cnt;
      }
      const double mean = sum / cnt, sd = std::sqrt(std::max(0.0, sum2 / cnt - mean * mean));
      for (const auto& q : s.region) s.used[q.i] = 0;
      grow(seed, static_cast<float>(std::cos(std::min(tau, 2 * sd))), sx, sy);
      if (static_cast<int>(s.region.size()) < min_pixels) continue;
      rc = rect_of(sx, sy);
      // ... then the region cut to a shrinking radius round the seed until it is dense enough.
      double far2 = 0;
      for (const auto& q : s.region) {
        const double x = q.x - seed_x, y = q.y - seed_y;
        far2 = std::max(far2, x * x + y * y);
      }
      double rad = std::sqrt(far2);
      for (int cut = 0; cut < opt.max_cuts && !dense(rc) && static_cast<int>(s.region.size()) >= min_pixels; ++cut) {
        rad *= 0.75;
        std::size_t kept = 0;
        sx = sy = 0;
        for (const auto& q : s.region) {
          const double x = q.x - seed_x, y = q.y - seed_y;
          if (x * x + y * y <= rad * rad) {
            sx += s.ux[q.i], sy += s.uy[q.i];
            s.region[kept++] = q;
          } else {
            s.used[q.i] = 0;
          }
        }
        s.region.resize(kept);
        if (static_cast<int>(kept) < min_pixels) break;
        rc = rect_of(sx, sy);
      }
      if (static_cast<int>(s.region.size()) < min_pixels || !dense(rc)) continue;
    }
    if (rc.lmax - rc.lmin < opt.min_length_px) continue;
    const int k = static_cast<int>(s.region.size());
    const int n = std::max(k, static_cast<int>(std::ceil(rc.length() * rc.width())));
    if (log_nt + log10_binomial_tail(n, k, p) >= -opt.log_eps) continue;
    Segment seg;
    seg.p0 = {rc.cx + 0.5 + rc.lmin * rc.ex, rc.cy + 0.5 + rc.lmin * rc.ey};
    seg.p1 = {rc.cx + 0.5 + rc.lmax * rc.ex, rc.cy + 0.5 + rc.lmax * rc.ey};
    seg.length = (seg.p1 - seg.p0).norm();
    seg.theta = std::atan2(seg.p1.y() - seg.p0.y(), seg.p1.x() - seg.p0.x());
    out.push_back(seg);
  }
  return out;
}

}  // namespace tagbench
