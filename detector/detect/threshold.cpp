#include "detect/threshold.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "detect/blur.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tagbench {
namespace {

// Tile min / max of one tile row: rows [y0, y1) of the image, tiles of t columns (the last one may
// be partial). The first row initialises, the others merge; T > 0 is t known at compile time, so
// the inner loops unroll and the merge vectorises.
template <int T>
void tile_row_minmax(const ImageF& img, int y0, int y1, int t_rt, float* tmin, float* tmax) {
  const int t = T > 0 ? T : t_rt;
  const int w = img.width, full = w / t;
  for (int y = y0; y < y1; ++y) {
    const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const bool first = y == y0;
    for (int tx = 0; tx < full; ++tx) {
      const float* p = row + tx * t;
      float mn = p[0], mx = p[0];
      for (int i = 1; i < t; ++i) {
        mn = std::min(mn, p[i]);
        mx = std::max(mx, p[i]);
      }
      tmin[tx] = first ? mn : std::min(tmin[tx], mn);
      tmax[tx] = first ? mx : std::max(tmax[tx], mx);
    }
    if (full * t < w) {  // the partial last tile
      float mn = row[full * t], mx = mn;
      for (int x = full * t + 1; x < w; ++x) {
        mn = std::min(mn, row[x]);
        mx = std::max(mx, row[x]);
      }
      tmin[full] = first ? mn : std::min(tmin[full], mn);
      tmax[full] = first ? mx : std::max(tmax[full], mx);
    }
  }
}

// 3-tap min and max along each row of a tw x th grid (the edge tiles only see their inner
// neighbour): the ends apart, so the middle loop is branch-free.
void minmax3_rows(const float* in_min, const float* in_max, float* out_min, float* out_max, int tw, int th) {
  for (int ty = 0; ty < th; ++ty) {
    const std::size_t o = static_cast<std::size_t>(ty) * static_cast<std::size_t>(tw);
    const float *a = in_min + o, *b = in_max + o;
    float *c = out_min + o, *d = out_max + o;
    if (tw == 1) {
      c[0] = a[0];
      d[0] = b[0];
      continue;
    }
    c[0] = std::min(a[0], a[1]);
    d[0] = std::max(b[0], b[1]);
    for (int x = 1; x + 1 < tw; ++x) {
      c[x] = std::min(std::min(a[x - 1], a[x]), a[x + 1]);
      d[x] = std::max(std::max(b[x - 1], b[x]), b[x + 1]);
    }
    c[tw - 1] = std::min(a[tw - 2], a[tw - 1]);
    d[tw - 1] = std::max(b[tw - 2], b[tw - 1]);
  }
}

// out[x] = op(a[x], b[x], c[x]) over a tile row: one output and three inputs, so the compiler's
// run-time overlap check stays small enough to vectorise.
template <class Op>
void combine3(const float* a, const float* b, const float* c, float* out, std::size_t n, Op op) {
  for (std::size_t x = 0; x < n; ++x) out[x] = op(op(a[x], b[x]), c[x]);
}

// The same along the columns: whole tile rows at a time (contiguous, vectorised).
void minmax3_cols(const float* in_min, const float* in_max, float* out_min, float* out_max, int tw, int th) {
  const std::size_t n = static_cast<std::size_t>(tw);
  const auto mn = [](float a, float b) { return std::min(a, b); };
  const auto mx = [](float a, float b) { return std::max(a, b); };
  for (int ty = 0; ty < th; ++ty) {
    const std::size_t o = static_cast<std::size_t>(ty) * n;
    const std::size_t up = ty > 0 ? o - n : o, down = ty + 1 < th ? o + n : o;  // clamped: the tile itself
    combine3(in_min + up, in_min + o, in_min + down, out_min + o, n, mn);
    combine3(in_max + up, in_max + o, in_max + down, out_max + o, n, mx);
  }
}

// Each tile's value copied to its t columns (T > 0: t at compile time).
template <int T>
void spread(const float* tmid, const std::uint8_t* tflat, int tw, int t_rt, float* mid, std::uint8_t* flat) {
  const int t = T > 0 ? T : t_rt;
  for (int tx = 0; tx < tw; ++tx)
    for (int i = 0; i < t; ++i) {
      mid[tx * t + i] = tmid[tx];
      flat[tx * t + i] = tflat[tx];
    }
}

}  // namespace

void adaptive_threshold(const ImageF& img, const ThresholdOptions& opt, ThresholdScratch& s, TernaryImage& out) {
  if (opt.tile_size < 1) throw std::invalid_argument("threshold tile size " + std::to_string(opt.tile_size) + " is below 1");
  if (!(opt.min_contrast >= 0) || !std::isfinite(opt.min_contrast))
    throw std::invalid_argument("threshold min_contrast must be finite and >= 0");
  if (!(opt.low_contrast >= 0) || !std::isfinite(opt.low_contrast) || !(opt.weber_ratio >= 0) ||
      !std::isfinite(opt.weber_ratio))
    throw std::invalid_argument("threshold low_contrast and weber_ratio must be finite and >= 0");
  if (!(opt.mean_sigma >= 0) || !std::isfinite(opt.mean_sigma))
    throw std::invalid_argument("threshold mean_sigma must be finite and >= 0");
  const int w = img.width, h = img.height, t = opt.tile_size;
  out.width = w;
  out.height = h;
  out.data.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  if (img.empty()) return;
  const int tw = (w + t - 1) / t, th = (h + t - 1) / t;
  const std::size_t nt = static_cast<std::size_t>(tw) * static_cast<std::size_t>(th);
  s.tile_min.resize(nt);
  s.tile_max.resize(nt);
  s.tmp_min.resize(nt);
  s.tmp_max.resize(nt);

  // 1. Tile min / max, a tile row at a time (sequential reads).
  for (int ty = 0; ty < th; ++ty) {
    const int y0 = ty * t, y1 = std::min(h, y0 + t);
    float* tmin = s.tile_min.data() + static_cast<std::size_t>(ty) * static_cast<std::size_t>(tw);
    float* tmax = s.tile_max.data() + static_cast<std::size_t>(ty) * static_cast<std::size_t>(tw);
    switch (t) {
      case 2: tile_row_minmax<2>(img, y0, y1, t, tmin, tmax); break;
      case 3: tile_row_minmax<3>(img, y0, y1, t, tmin, tmax); break;
      case 4: tile_row_minmax<4>(img, y0, y1, t, tmin, tmax); break;
      default: tile_row_minmax<0>(img, y0, y1, t, tmin, tmax); break;
    }
  }
  // 2. Widen to the 3 x 3 tiles around each tile (separable).
  minmax3_rows(s.tile_min.data(), s.tile_max.data(), s.tmp_min.data(), s.tmp_max.data(), tw, th);
  minmax3_cols(s.tmp_min.data(), s.tmp_max.data(), s.tile_min.data(), s.tile_max.data(), tw, th);

  // 3. Class each pixel against its tile's midpoint: per tile row, every tile's midpoint and flatness
  // (0xFF where max - min < min_contrast) are computed, then spread out to the tile's columns once,
  // so the per-pixel loop is branch-free and vectorises.
  s.mid.resize(static_cast<std::size_t>(tw) * static_cast<std::size_t>(t));
  s.flat.resize(s.mid.size());
  s.tile_mid.resize(static_cast<std::size_t>(tw));
  s.tile_flat.resize(static_cast<std::size_t>(tw));
  const bool by_mean = opt.mean_sigma > 0;
  if (by_mean) gaussian_blur(img, opt.mean_sigma, s.mean_tmp, s.mean);
  float* mid = s.mid.data();
  std::uint8_t* flat = s.flat.data();
  for (int ty = 0; ty < th; ++ty) {
    const std::size_t trow = static_cast<std::size_t>(ty) * static_cast<std::size_t>(tw);
    const float* tmin = s.tile_min.data() + trow;
    const float* tmax = s.tile_max.data() + trow;
    float* tmid = s.tile_mid.data();
    std::uint8_t* tflat = s.tile_flat.data();
    const float min_contrast = opt.min_contrast;
    // Flat below min_contrast, unless the relative floor (ThresholdOptions) classes it; with
    // low_contrast >= min_contrast (its default) that floor never applies.
    const float low = opt.low_contrast, weber = opt.weber_ratio;
    int tx = 0;
#if defined(__SSE2__)
    // Four tiles at a time, the same comparisons and arithmetic as below.
    for (; tx + 4 <= tw; tx += 4) {
      const __m128 mn = _mm_loadu_ps(tmin + tx), mx = _mm_loadu_ps(tmax + tx), d = _mm_sub_ps(mx, mn);
      const __m128 f = _mm_and_ps(_mm_cmplt_ps(d, _mm_set1_ps(min_contrast)),
                                  _mm_or_ps(_mm_cmplt_ps(d, _mm_set1_ps(low)), _mm_cmplt_ps(d, _mm_mul_ps(_mm_set1_ps(weber), mx))));
      const __m128i f8 = _mm_packs_epi16(_mm_packs_epi32(_mm_castps_si128(f), _mm_setzero_si128()), _mm_setzero_si128());
      const int f4 = _mm_cvtsi128_si32(f8);
      std::memcpy(tflat + tx, &f4, 4);
      _mm_storeu_ps(tmid + tx, _mm_add_ps(mn, _mm_mul_ps(_mm_set1_ps(0.5f), d)));
    }
#endif
    for (; tx < tw; ++tx) {
      const float mn = tmin[tx], mx = tmax[tx], d = mx - mn;
      // Bitwise, not short-circuit: no branch, so the loop vectorises (the same value).
      tflat[tx] = (d < min_contrast) & ((d < low) | (d < weber * mx)) ? 0xFF : 0;
      tmid[tx] = mn + 0.5f * d;
    }
    switch (t) {  // columns past the image's last one (a partial last tile) are filled but never read
      case 2: spread<2>(tmid, tflat, tw, t, mid, flat); break;
      case 3: spread<3>(tmid, tflat, tw, t, mid, flat); break;
      case 4: spread<4>(tmid, tflat, tw, t, mid, flat); break;
      default: spread<0>(tmid, tflat, tw, t, mid, flat); break;
    }
    for (int y = ty * t, ye = std::min(h, y + t); y < ye; ++y) {
      const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      std::uint8_t* o = out.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
      // The threshold of this row: the tile midpoints, or the local mean's own row.
      const float* thr = by_mean ? s.mean.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w) : s.mid.data();
      int x = 0;
#if defined(__SSE2__)
      // 16 pixels at a time: four float comparisons packed to bytes (all-ones light, zero dark,
      // which are kTernaryLight and kTernaryDark), then the flat mask as below.
      static_assert(kTernaryLight == 0xFF && kTernaryDark == 0);
      for (; x + 16 <= w; x += 16) {
        __m128i c[4];
        for (int k = 0; k < 4; ++k)
          c[k] = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(row + x + 4 * k), _mm_loadu_ps(thr + x + 4 * k)));
        const __m128i cls = _mm_packs_epi16(_mm_packs_epi32(c[0], c[1]), _mm_packs_epi32(c[2], c[3]));
        const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(flat + x));
        const __m128i o16 = _mm_or_si128(_mm_andnot_si128(f, cls), _mm_and_si128(f, _mm_set1_epi8(static_cast<char>(kTernaryUnknown))));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(o + x), o16);
      }
#endif
      for (; x < w; ++x) {
        // Light 255, dark 0; a flat column's 0xFF mask turns either into 127 (kTernaryUnknown).
        const std::uint8_t cls = row[x] > thr[x] ? kTernaryLight : kTernaryDark;
        o[x] = static_cast<std::uint8_t>((cls & ~flat[x]) | (kTernaryUnknown & flat[x]));
      }
    }
  }
}

TernaryImage adaptive_threshold(const ImageF& img, const ThresholdOptions& opt) {
  ThresholdScratch s;
  TernaryImage out;
  adaptive_threshold(img, opt, s, out);
  return out;
}

}  // namespace tagbench
