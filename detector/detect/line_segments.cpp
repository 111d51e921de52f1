#include "detect/line_segments.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
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
  if (!(opt.min_gradient > 0) || !(opt.angle_tolerance_deg > 0 && opt.angle_tolerance_deg <= 90) ||
      opt.straight_sides < 0 || opt.straight_sides > 2 || !(opt.straight_check_px > 0))
    throw std::invalid_argument(
        "LineSegmentOptions: min_gradient must be > 0, angle_tolerance_deg in (0, 90], straight_sides in 0..2 and "
        "straight_check_px > 0");
  std::vector<Segment> out;
  if (img.width < 3 || img.height < 3) return out;
  const float floor = static_cast<float>(opt.min_gradient / 255.0);
  // Flat blocks (skip_flat_blocks). A gradient (2 x 2 mask on the blurred image, below) at grid
  // point (x, y) mixes image pixels within r + 1 of it (r the blur's radius), and each of its two
  // components is at most their grey range, so its magnitude at most sqrt 2 times that: a block
  // whose neighbourhood's range is below floor / sqrt 2 (less 1e-5 for the float sums) has no pixel
  // at the floor. Such blocks are not differentiated, nor blurred where no busy block needs them.
  constexpr int kBlock = 16;
  const int r = opt.sigma > 0 ? gaussian_radius(opt.sigma) : 0;
  const int bw = (img.width + kBlock - 1) / kBlock, bh = (img.height + kBlock - 1) / kBlock;
  const std::size_t nb = static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh);
  s.busy.assign(nb, 1);
  bool all_busy = true;
  if (opt.skip_flat_blocks) {
    // Each block row's range per column first (element-wise over rows: vectorised), then per block.
    s.block_lo.resize(nb), s.block_hi.resize(nb);
    s.column_lo.resize(static_cast<std::size_t>(img.width)), s.column_hi.resize(static_cast<std::size_t>(img.width));
    float *clo = s.column_lo.data(), *chi = s.column_hi.data();
    for (int by = 0; by < bh; ++by) {
      const int y0 = by * kBlock, y1 = std::min(img.height, y0 + kBlock);
      std::copy_n(img.data.data() + img.index(0, y0), img.width, clo);
      std::copy_n(img.data.data() + img.index(0, y0), img.width, chi);
      for (int y = y0 + 1; y < y1; ++y) {
        const float* row = img.data.data() + img.index(0, y);
        for (int x = 0; x < img.width; ++x) {
          clo[x] = row[x] < clo[x] ? row[x] : clo[x];
          chi[x] = row[x] > chi[x] ? row[x] : chi[x];
        }
      }
      for (int bx = 0; bx < bw; ++bx) {
        float l = clo[bx * kBlock], h = chi[bx * kBlock];
        for (int x = bx * kBlock + 1; x < std::min(img.width, (bx + 1) * kBlock); ++x) l = std::min(l, clo[x]), h = std::max(h, chi[x]);
        s.block_lo[static_cast<std::size_t>(by * bw + bx)] = l, s.block_hi[static_cast<std::size_t>(by * bw + bx)] = h;
      }
    }
    const int reach = 1 + r / kBlock;  // blocks either way holding every pixel within r + 1
    const float limit = floor / std::numbers::sqrt2_v<float> - 1e-5f;
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        float l = std::numeric_limits<float>::infinity(), h = -l;
        for (int j = std::max(0, by - reach); j <= std::min(bh - 1, by + reach); ++j)
          for (int i = std::max(0, bx - reach); i <= std::min(bw - 1, bx + reach); ++i) {
            const std::size_t q = static_cast<std::size_t>(j * bw + i);
            l = std::min(l, s.block_lo[q]), h = std::max(h, s.block_hi[q]);
          }
        const bool busy = !(h - l < limit);
        s.busy[static_cast<std::size_t>(by * bw + bx)] = busy;
        all_busy = all_busy && busy;
      }
  }
  if (opt.sigma <= 0) {
    // no blur: the gradients are taken on img itself
  } else if (all_busy) {
    gaussian_blur(img, opt.sigma, s.tmp, s.blurred);
  } else {
    // A busy block's gradients read the pixels of the blocks right of and below it too.
    s.need.assign(nb, 0);
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx)
        for (int j = std::max(0, by - 1); j <= by; ++j)
          for (int i = std::max(0, bx - 1); i <= bx; ++i)
            if (s.busy[static_cast<std::size_t>(j * bw + i)]) s.need[static_cast<std::size_t>(by * bw + bx)] = 1;
    gaussian_blur_blocks(img, opt.sigma, kBlock, s.need, s.tmp, s.blurred);
  }
  const ImageF& b = opt.sigma > 0 ? s.blurred : img;
  // Gradients at pixel corners: a (W - 1) x (H - 1) grid, entry (x, y) at image point (x + 0.5, y + 0.5),
  // stored with a rim: index (y + 1) * P + x + 1.
  const int W = img.width - 1, H = img.height - 1, P = W + 2;
  const std::size_t N = static_cast<std::size_t>(P) * static_cast<std::size_t>(H + 2);
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  s.dir.resize(N);
  std::fill_n(s.dir.begin(), P, LineSegmentScratch::Direction{kNaN, kNaN});  // the rim
  std::fill_n(s.dir.end() - P, P, LineSegmentScratch::Direction{kNaN, kNaN});
  for (int y = 0; y < H; ++y) {
    s.dir[static_cast<std::size_t>(y + 1) * static_cast<std::size_t>(P)] = {kNaN, kNaN};
    s.dir[static_cast<std::size_t>(y + 2) * static_cast<std::size_t>(P) - 1] = {kNaN, kNaN};
  }
  s.mag.resize(N);
  s.candidates.clear();
  if (!all_busy) {
    s.flat_row.assign(static_cast<std::size_t>(W), LineSegmentScratch::Direction{kNaN, kNaN});
    // Each block's part: 1 busy (differentiated); 2 flat but within reach of a busy block, set to NaN
    // (region growing steps a pixel from a region's pixels, the straight check straight_check_px; a
    // block next to a candidate is mostly busy itself, this makes it so for any reach); 0 flat and out of
    // every reach: never read, so left as it is (its directions and magnitudes are whatever a
    // previous image left there). Most of a flat image's dir is then not written at all.
    const int ring = std::max(1, static_cast<int>(std::ceil((opt.straight_sides > 0 ? opt.straight_check_px + 1 : 1) / kBlock)));
    s.part.assign(nb, 0);
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        if (!s.busy[static_cast<std::size_t>(by * bw + bx)]) continue;
        for (int j = std::max(0, by - ring); j <= std::min(bh - 1, by + ring); ++j)
          for (int i = std::max(0, bx - ring); i <= std::min(bw - 1, bx + ring); ++i) {
            std::uint8_t& q = s.part[static_cast<std::size_t>(j * bw + i)];
            q = std::max<std::uint8_t>(q, s.busy[static_cast<std::size_t>(j * bw + i)] ? 1 : 2);
          }
      }
  }
  float max_mag = 0;
  s.row_first.resize(static_cast<std::size_t>(H) + 1);
  for (int y = 0; y < H; ++y) {
    s.row_first[static_cast<std::size_t>(y)] = static_cast<std::uint32_t>(s.candidates.size());
    const float* r0 = b.data.data() + b.index(0, y);
    const float* r1 = r0 + b.width;
    const std::size_t row = static_cast<std::size_t>(y + 1) * static_cast<std::size_t>(P) + 1;
    float* m_row = s.mag.data() + row;
    const auto gradient = [&](int x) {  // the 2 x 2 mask at (x + 0.5, y + 0.5)
      return std::array<float, 2>{0.5f * (r0[x + 1] + r1[x + 1] - r0[x] - r1[x]),
                                  0.5f * (r1[x] + r1[x + 1] - r0[x] - r0[x + 1])};
    };
    const auto differentiate = [&](int x0, int x1) {
      // Directions and the candidate list without a branch per pixel (the floor test is as unpredictable
      // as the texture): every pixel's index is written and the count advanced only for a candidate.
      const std::size_t first = s.candidates.size();
      s.candidates.resize(first + static_cast<std::size_t>(x1 - x0));
      std::uint32_t* cand = s.candidates.data() + first;
      std::size_t count = 0;
      LineSegmentScratch::Direction* d = s.dir.data() + row;
      float top = max_mag;
      // Selections by bit masks (a float select compiles to a branch): `kept` where the mask is clear,
      // `dropped` where it is all ones.
      const auto choose = [](std::uint32_t drop, float kept, float dropped) {
        return std::bit_cast<float>((std::bit_cast<std::uint32_t>(kept) & ~drop) | (std::bit_cast<std::uint32_t>(dropped) & drop));
      };
      // Magnitudes and directions first, in a loop of their own without a branch (vectorised); then
      // the candidates and the maximum, which do not vectorise (the same numbers either way).
      for (int x = x0; x < x1; ++x) {
        const auto [gx, gy] = gradient(x);
        const float m = std::sqrt(gx * gx + gy * gy);
        m_row[x] = m;
        const std::uint32_t drop = 0u - static_cast<std::uint32_t>(m < floor);
        const float div = choose(drop, m, 1.0f);  // no division by zero where dropped
        d[x] = {choose(drop, gx / div, kNaN), choose(drop, gy / div, kNaN)};
      }
      for (int x = x0; x < x1; ++x) {
        const float m = m_row[x];
        const bool keep = !(m < floor);
        const std::uint32_t drop = 0u - static_cast<std::uint32_t>(!keep);
        cand[count] = static_cast<std::uint32_t>(row + static_cast<std::size_t>(x));
        count += keep;
        top = std::max(top, choose(drop, m, 0.0f));  // the maximum is >= 0: a dropped pixel leaves it
      }
      max_mag = top;
      s.candidates.resize(first + count);
    };
    if (all_busy) {
      differentiate(0, W);
      continue;
    }
    const std::uint8_t* part = s.part.data() + static_cast<std::size_t>(y / kBlock) * static_cast<std::size_t>(bw);
    for (int bx = 0; bx * kBlock < W;) {
      int end = bx + 1;
      while (end * kBlock < W && part[end] == part[bx]) ++end;
      const int x0 = bx * kBlock, x1 = std::min(W, end * kBlock);
      if (part[bx] == 1)
        differentiate(x0, x1);
      else if (part[bx] == 2)  // a block copy from a row of NaN pairs (a fill of pairs is 8-byte stores)
        std::copy_n(s.flat_row.begin(), x1 - x0, s.dir.begin() + static_cast<std::ptrdiff_t>(row) + x0);
      bx = end;
    }
  }
  s.row_first[static_cast<std::size_t>(H)] = static_cast<std::uint32_t>(s.candidates.size());
  const double tau = opt.angle_tolerance_deg * std::numbers::pi / 180;
  const float cos_tau = static_cast<float>(std::cos(tau));
  const std::array<std::int64_t, 8> step{-P - 1, -P, -P + 1, -1, 1, P - 1, P, P + 1};
  if (opt.straight_sides > 0) {
    // A pixel of a straight edge has pixels of the same direction straight_check_px away along the
    // edge, on both sides but at its ends; blurred noise does not beyond its short correlation.
    // Decided for every pixel on the same grid, then applied.
    const float reach = static_cast<float>(opt.straight_check_px);
    s.aligned.resize(s.candidates.size());
    // Rounding half away from zero, branch-free (candidates' directions are never NaN; -0 gives 0
    // either way).
    const auto nearest = [](float v) { return static_cast<int>(v + std::copysign(0.5f, v)); };
    const LineSegmentScratch::Direction* dir = s.dir.data();
    const auto rows = static_cast<unsigned>(H + 2), cols = static_cast<unsigned>(P);
    for (int y = 0; y < H; ++y) {  // candidates row by row (they are in raster order); y + 1 on the padded grid
      const std::uint32_t row_start = static_cast<std::uint32_t>(y + 1) * static_cast<std::uint32_t>(P);
      for (std::uint32_t k = s.row_first[static_cast<std::size_t>(y)]; k < s.row_first[static_cast<std::size_t>(y) + 1]; ++k) {
        const std::uint32_t i = s.candidates[k];
        const LineSegmentScratch::Direction d = dir[i];
        const int x = static_cast<int>(i - row_start);
        const int ox = nearest(-d.uy * reach), oy = nearest(d.ux * reach);
        int n = 0;
        for (const int sgn : {-1, 1}) {
          const int qx = x + sgn * ox, qy = y + 1 + sgn * oy;
          if (static_cast<unsigned>(qx) >= cols || static_cast<unsigned>(qy) >= rows) continue;
          const LineSegmentScratch::Direction e = dir[static_cast<std::size_t>(qy) * static_cast<std::size_t>(P) + static_cast<std::size_t>(qx)];
          n += e.ux * d.ux + e.uy * d.uy >= cos_tau;  // NaN: false
        }
        s.aligned[k] = static_cast<std::uint8_t>(n);
      }
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < s.candidates.size(); ++k) {
      if (s.aligned[k] >= opt.straight_sides)
        s.candidates[kept++] = s.candidates[k];
      else if (!opt.straight_seeds_only)
        s.dir[s.candidates[k]] = {kNaN, kNaN};
    }
    s.candidates.resize(kept);
  }
  // Pseudo-order by magnitude, strongest first (LSD's bins), raster order within a bin.
  constexpr int bins = 1024;
  s.bin_count.assign(static_cast<std::size_t>(bins) + 1, 0);
  s.bin.resize(s.candidates.size());
  const float to_bin = max_mag > 0 ? (bins - 1) / max_mag : 0.0f;
  for (std::size_t k = 0; k < s.candidates.size(); ++k) {
    const int bin = bins - 1 - static_cast<int>(s.mag[s.candidates[k]] * to_bin);
    s.bin[k] = static_cast<std::uint16_t>(bin);
    ++s.bin_count[static_cast<std::size_t>(bin) + 1];
  }
  for (int k = 0; k < bins; ++k) s.bin_count[static_cast<std::size_t>(k) + 1] += s.bin_count[static_cast<std::size_t>(k)];
  s.order.resize(s.candidates.size());
  for (std::size_t k = 0; k < s.candidates.size(); ++k) s.order[s.bin_count[s.bin[k]]++] = s.candidates[k];

  const double p = opt.angle_tolerance_deg / 180.0;
  const double log_nt = 2.5 * (std::log10(static_cast<double>(W)) + std::log10(static_cast<double>(H))) + std::log10(11.0);
  // A region of k pixels filling its rectangle exactly (n = k) is meaningful only when k log10(1/p) > log_nt.
  const int min_pixels = static_cast<int>(std::ceil((log_nt + opt.log_eps) / -std::log10(p)));
  const std::size_t max_region = opt.max_region_pixels > 0 ? static_cast<std::size_t>(opt.max_region_pixels) : N;
  const std::array<int, 8> step_x{-1, 0, 1, -1, 1, -1, 0, 1}, step_y{-1, -1, -1, 0, 0, 1, 1, 1};
  const auto take = [&](std::uint32_t i, std::int32_t x, std::int32_t y) {
    const LineSegmentScratch::Direction d = s.dir[i];
    s.region.push_back({x, y, i, d.ux, d.uy});
    s.dir[i] = {kNaN, kNaN};  // used
  };
  const auto release = [&]() {
    for (const auto& q : s.region) s.dir[q.i] = {q.ux, q.uy};
  };
  const auto grow = [&](std::uint32_t seed, float cos_tol, double& sx, double& sy) {
    s.region.clear();
    take(seed, static_cast<std::int32_t>(seed % static_cast<std::uint32_t>(P)) - 1,
         static_cast<std::int32_t>(seed / static_cast<std::uint32_t>(P)) - 1);
    // Within the tolerance of the mean direction (sx, sy) / |(sx, sy)|: d . s >= cos_tol |s|, squared
    // so that no root is taken per pixel (cos_tol >= 0 as the tolerance is at most 90 degrees).
    float ax = s.region[0].ux, ay = s.region[0].uy;
    const float c2 = cos_tol * cos_tol;
    float n2 = 1;
    for (std::size_t r = 0; r < s.region.size() && s.region.size() <= max_region; ++r) {
      const std::int64_t i = s.region[r].i;
      const std::int32_t px = s.region[r].x, py = s.region[r].y;
      for (int k = 0; k < 8; ++k) {
        const std::uint32_t j = static_cast<std::uint32_t>(i + step[static_cast<std::size_t>(k)]);
        const LineSegmentScratch::Direction d = s.dir[j];
        const float dot = d.ux * ax + d.uy * ay;
        if (!((dot >= 0) & (dot * dot >= c2 * n2))) continue;  // NaN: used, below the floor or the rim
        take(j, px + step_x[static_cast<std::size_t>(k)], py + step_y[static_cast<std::size_t>(k)]);
        ax += d.ux, ay += d.uy;
        n2 = ax * ax + ay * ay;
      }
    }
    sx = ax, sy = ay;
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
    if (std::isnan(s.dir[seed].ux)) continue;
    double sx, sy;
    grow(seed, cos_tau, sx, sy);
    if (static_cast<int>(s.region.size()) < min_pixels || s.region.size() > max_region) continue;
    Rect rc = rect_of(sx, sy);
    if (!dense(rc)) {
      // LSD's refinement: a tolerance from the spread of directions near the seed, grown again ...
      const double sxs = s.region[0].ux, sys = s.region[0].uy;  // the seed's
      const double rad2 = rc.width() * rc.width();
      const int seed_x = s.region[0].x, seed_y = s.region[0].y;
      double sum = 0, sum2 = 0;
      int cnt = 0;
      for (const auto& q : s.region) {
        const double x = q.x - seed_x, y = q.y - seed_y;
        if (x * x + y * y > rad2) continue;
        const double a = std::atan2(q.ux * sys - q.uy * sxs, q.ux * sxs + q.uy * sys);
        sum += a, sum2 += a * a, ++cnt;
      }
      const double mean = sum / cnt, sd = std::sqrt(std::max(0.0, sum2 / cnt - mean * mean));
      release();
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
            sx += q.ux, sy += q.uy;
            s.region[kept++] = q;
          } else {
            s.dir[q.i] = {q.ux, q.uy};
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
