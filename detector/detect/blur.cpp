#include "detect/blur.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace tagbench {
namespace {

// Sets the size without releasing storage: resize() keeps the capacity, so a buffer reused for
// frames of one size is never reallocated.
void reshape(ImageF& img, int w, int h) {
  img.width = w;
  img.height = h;
  img.data.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
}

#if defined(__SSE2__)
// Eight outputs dst[0..8): output j sums k[t] * tap(t)[j] over the taps in order from 0, in float,
// the sums held in two registers, each output stored once. tap(t): the eight inputs of tap t.
template <class Tap>
void sum_eight(const std::vector<float>& k, Tap tap, float* dst) {
  __m128 s0 = _mm_setzero_ps(), s1 = _mm_setzero_ps();
  for (std::size_t t = 0; t < k.size(); ++t) {
    const __m128 kt = _mm_set1_ps(k[t]);
    const float* p = tap(t);
    s0 = _mm_add_ps(s0, _mm_mul_ps(kt, _mm_loadu_ps(p)));
    s1 = _mm_add_ps(s1, _mm_mul_ps(kt, _mm_loadu_ps(p + 4)));
  }
  _mm_storeu_ps(dst, s0);
  _mm_storeu_ps(dst + 4, s1);
}
#endif

// The output columns X of filter_rows whose taps all fall inside the row (no clamping): [lo, hi).
struct Interior {
  int lo, hi;
};
Interior unclamped_columns(int w, int taps, int first, int step, int out_w) {
  const int lo = std::min(out_w, std::max(0, (-first + step - 1) / step));
  return {lo, std::max(lo, std::min(out_w, (w - (first + taps - 1) + step - 1) / step))};
}

// Output columns [X0, X1) of one row of filter_rows (`in`: its unclamped columns): src's row `row`
// of width w correlated with kernel k (taps for offsets first..first+k.size()-1), sampled at
// x = step * X + first, clamped at the borders.
void filter_row_span(const float* row, int w, const std::vector<float>& k, int first, int step, Interior in, int X0,
                     int X1, float* dst) {
  const int taps = static_cast<int>(k.size());
  const int a = std::clamp(in.lo, X0, X1), b = std::clamp(in.hi, a, X1);  // [a, b): no clamping
  const auto clamped = [&](int X) {
    float s = 0.0f;
    for (int t = 0; t < taps; ++t) s += k[t] * row[std::clamp(step * X + first + t, 0, w - 1)];
    return s;
  };
  for (int X = X0; X < a; ++X) dst[X] = clamped(X);
  if (a >= b) {
    // no unclamped column in the span
  } else if (step == 1) {
    // Eight outputs at a time (sum_eight: each stored once, where summing into dst tap by tap loaded
    // and stored it once a tap). Each output still sums its taps in the order 0, 1, ... in float from
    // 0: the values of the loop below, bit for bit.
    const float* p = row + first;  // output X reads p[X + t]; a >= in.lo >= -first: inside the row
    int X = a;
#if defined(__SSE2__)
    for (; X + 8 <= b; X += 8) sum_eight(k, [&](std::size_t t) { return p + X + t; }, dst + X);
#endif
    for (; X < b; ++X) {
      float s = 0.0f;
      for (int t = 0; t < taps; ++t) s += k[static_cast<std::size_t>(t)] * p[X + t];
      dst[X] = s;
    }
  } else {
    for (int X = a; X < b; ++X) {
      const float* p = row + step * X + first;
      float s = 0.0f;
      for (int t = 0; t < taps; ++t) s += k[t] * p[t];
      dst[X] = s;
    }
  }
  for (int X = b; X < X1; ++X) dst[X] = clamped(X);
}

// Correlates every row of src with kernel k (taps for offsets first..first+k.size()-1), sampling
// src at x = step * X + offset for output X in [0, out_w), with clamped borders. step = 1 is a plain
// horizontal blur, step = 2 the decimating pass of blur_and_halve. Every output value is written,
// so `out` is only resized (its storage is reused when big enough).
void filter_rows(const ImageF& src, const std::vector<float>& k, int first, int step, int out_w, ImageF& out) {
  reshape(out, out_w, src.height);
  const Interior in = unclamped_columns(src.width, static_cast<int>(k.size()), first, step, out_w);
  for (int y = 0; y < src.height; ++y)
    filter_row_span(&src.data[src.index(0, y)], src.width, k, first, step, in, 0, out_w, &out.data[out.index(0, y)]);
}

// Output columns [X0, X1) of output row Y of filter_cols: source rows step * Y + first + t (clamped),
// whole rows at a time so the inner loop runs along contiguous memory, accumulated from zero.
void filter_col_span(const ImageF& src, const std::vector<float>& k, int first, int step, int Y, int X0, int X1,
                     float* dst) {
  const auto source_row = [&](std::size_t t) {
    return &src.data[src.index(0, std::clamp(step * Y + first + static_cast<int>(t), 0, src.height - 1))];
  };
  constexpr std::size_t kMaxTaps = 64;  // sigma up to about 10 px; wider kernels take the plain loop
  int x = X0;
#if defined(__SSE2__)
  // As filter_row_span: eight outputs at a time (sum_eight).
  if (k.size() <= kMaxTaps) {
    std::array<const float*, kMaxTaps> rows{};
    for (std::size_t t = 0; t < k.size(); ++t) rows[t] = source_row(t);
    for (; x + 8 <= X1; x += 8) sum_eight(k, [&](std::size_t t) { return rows[t] + x; }, dst + x);
  }
#endif
  std::fill(dst + x, dst + X1, 0.0f);
  for (std::size_t t = 0; t < k.size(); ++t) {
    const float* row = source_row(t);
    const float kt = k[t];
    for (int i = x; i < X1; ++i) dst[i] += kt * row[i];
  }
}

// The vertical counterpart of filter_rows: output row Y combines source rows step * Y + first + t.
void filter_cols(const ImageF& src, const std::vector<float>& k, int first, int step, int out_h, ImageF& out) {
  reshape(out, src.width, out_h);
  for (int Y = 0; Y < out_h; ++Y) filter_col_span(src, k, first, step, Y, 0, src.width, &out.data[out.index(0, Y)]);
}

// The Gaussian convolved with the 2-tap box [1/2, 1/2]: offsets -r..r+1 relative to 2X.
std::vector<float> box_folded_kernel(const std::vector<float>& g) {
  std::vector<float> c(g.size() + 1, 0.0f);
  for (std::size_t i = 0; i < g.size(); ++i) {
    c[i] += 0.5f * g[i];
    c[i + 1] += 0.5f * g[i];
  }
  return c;
}

}  // namespace

int gaussian_radius(double sigma) { return sigma > 0.0 ? static_cast<int>(std::ceil(3.0 * sigma)) : 0; }

std::vector<float> gaussian_kernel(double sigma) {
  const int r = gaussian_radius(sigma);
  if (r == 0) return {1.0f};
  std::vector<double> g(static_cast<std::size_t>(2 * r + 1));
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) sum += g[static_cast<std::size_t>(i + r)] = std::exp(-0.5 * i * i / (sigma * sigma));
  std::vector<float> k(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) k[i] = static_cast<float>(g[i] / sum);
  return k;
}

ImageF gaussian_blur(const ImageF& img, double sigma) {
  ImageF tmp, out;
  gaussian_blur(img, sigma, tmp, out);
  return out;
}

void gaussian_blur(const ImageF& img, double sigma, ImageF& tmp, ImageF& out) {
  if (sigma <= 0.0 || img.empty()) {
    out = img;  // vector copy-assignment reuses out's storage when it is big enough
    return;
  }
  const std::vector<float> k = gaussian_kernel(sigma);
  const int r = gaussian_radius(sigma);
  filter_rows(img, k, -r, 1, img.width, tmp);
  filter_cols(tmp, k, -r, 1, img.height, out);
}

void gaussian_blur_blocks(const ImageF& img, double sigma, int block, std::span<const std::uint8_t> need, ImageF& tmp,
                          ImageF& out) {
  const int w = img.width, h = img.height;
  const int bw = block >= 1 ? (w + block - 1) / block : 0, bh = block >= 1 ? (h + block - 1) / block : 0;
  if (block < 1 || need.size() != static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh))
    throw std::invalid_argument("gaussian_blur_blocks: block must be >= 1 and need hold one entry per block");
  if (sigma <= 0.0 || img.empty()) {
    out = img;
    return;
  }
  const std::vector<float> k = gaussian_kernel(sigma);
  const int r = gaussian_radius(sigma);
  reshape(tmp, w, h);
  reshape(out, w, h);
  // The horizontal pass is needed on the rows the vertical pass reads: r rows either way.
  const int reach = (r + block - 1) / block;
  std::vector<std::uint8_t> rows_need(need.size(), 0);
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx)
      for (int j = std::max(0, by - reach); j <= std::min(bh - 1, by + reach); ++j)
        if (need[static_cast<std::size_t>(j * bw + bx)]) {
          rows_need[static_cast<std::size_t>(by * bw + bx)] = 1;
          break;
        }
  // Calls f(x0, x1) for every run of wanted blocks on the block row of image row y (pixels [x0, x1)).
  const auto runs = [&](std::span<const std::uint8_t> m, int y, auto&& f) {
    const std::uint8_t* row = m.data() + static_cast<std::size_t>(y / block) * static_cast<std::size_t>(bw);
    for (int bx = 0; bx < bw;) {
      if (!row[bx]) {
        ++bx;
        continue;
      }
      int end = bx;
      while (end < bw && row[end]) ++end;
      f(bx * block, std::min(w, end * block));
      bx = end;
    }
  };
  // filter_rows' and filter_cols' own spans, on the runs of blocks wanted.
  const Interior in = unclamped_columns(w, static_cast<int>(k.size()), -r, 1, w);
  for (int y = 0; y < h; ++y) {
    const float* row = &img.data[img.index(0, y)];
    float* dst = &tmp.data[tmp.index(0, y)];
    runs(rows_need, y, [&](int x0, int x1) { filter_row_span(row, w, k, -r, 1, in, x0, x1, dst); });
  }
  for (int Y = 0; Y < h; ++Y) {
    float* dst = &out.data[out.index(0, Y)];
    runs(need, Y, [&](int x0, int x1) { filter_col_span(tmp, k, -r, 1, Y, x0, x1, dst); });
  }
}

ImageF half_resolution(const ImageF& img) {
  ImageF out;
  half_resolution(img, out);
  return out;
}

void half_resolution(const ImageF& img, ImageF& out) {
  reshape(out, img.width / 2, img.height / 2);
  if (out.empty()) return;
  for (int Y = 0; Y < out.height; ++Y) {
    const float* a = &img.data[img.index(0, 2 * Y)];
    const float* b = &img.data[img.index(0, 2 * Y + 1)];
    float* dst = &out.data[out.index(0, Y)];
    for (int X = 0; X < out.width; ++X)
      dst[X] = 0.25f * (a[2 * X] + a[2 * X + 1] + b[2 * X] + b[2 * X + 1]);
  }
}

ImageF blur_and_halve(const ImageF& img, double sigma) {
  ImageF tmp, out;
  blur_and_halve(img, sigma, tmp, out);
  return out;
}

void blur_and_halve(const ImageF& img, double sigma, ImageF& tmp, ImageF& out) {
  if (sigma <= 0.0 || img.width < 2 || img.height < 2) return half_resolution(img, out);
  const int r = gaussian_radius(sigma);
  const std::vector<float> c = box_folded_kernel(gaussian_kernel(sigma));
  // Decimate along x while filtering the rows, then along y while filtering the columns.
  filter_rows(img, c, -r, 2, img.width / 2, tmp);
  filter_cols(tmp, c, -r, 2, img.height / 2, out);
}

}  // namespace tagbench
