#include "detect/threshold.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tagbench {
namespace {

// 3-tap running min and max along one axis of a tw x th grid (clamped ends: the edge tile only sees
// its inner neighbour). stride 1 filters rows, stride tw filters columns.
void minmax3(const std::vector<float>& in_min, const std::vector<float>& in_max, std::vector<float>& out_min,
             std::vector<float>& out_max, int tw, int th, bool along_x) {
  for (int ty = 0; ty < th; ++ty)
    for (int tx = 0; tx < tw; ++tx) {
      const std::size_t i = static_cast<std::size_t>(ty) * static_cast<std::size_t>(tw) + static_cast<std::size_t>(tx);
      float mn = in_min[i], mx = in_max[i];
      const int pos = along_x ? tx : ty, n = along_x ? tw : th;
      const std::size_t step = along_x ? 1 : static_cast<std::size_t>(tw);
      if (pos > 0) {
        mn = std::min(mn, in_min[i - step]);
        mx = std::max(mx, in_max[i - step]);
      }
      if (pos + 1 < n) {
        mn = std::min(mn, in_min[i + step]);
        mx = std::max(mx, in_max[i + step]);
      }
      out_min[i] = mn;
      out_max[i] = mx;
    }
}

}  // namespace

void adaptive_threshold(const ImageF& img, const ThresholdOptions& opt, ThresholdScratch& s, TernaryImage& out) {
  if (opt.tile_size < 1) throw std::invalid_argument("threshold tile size " + std::to_string(opt.tile_size) + " is below 1");
  if (!(opt.min_contrast >= 0) || !std::isfinite(opt.min_contrast))
    throw std::invalid_argument("threshold min_contrast must be finite and >= 0");
  const int w = img.width, h = img.height, t = opt.tile_size;
  out.width = w;
  out.height = h;
  out.data.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  if (img.empty()) return;
  const int tw = (w + t - 1) / t, th = (h + t - 1) / t;
  const std::size_t nt = static_cast<std::size_t>(tw) * static_cast<std::size_t>(th);
  s.tile_min.assign(nt, 2.0f);
  s.tile_max.assign(nt, -1.0f);
  s.tmp_min.resize(nt);
  s.tmp_max.resize(nt);

  // 1. Tile min / max, one image row at a time (sequential reads).
  for (int y = 0; y < h; ++y) {
    const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    float* tmin = s.tile_min.data() + static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
    float* tmax = s.tile_max.data() + static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
    for (int tx = 0; tx < tw; ++tx) {
      const int x0 = tx * t, x1 = std::min(w, x0 + t);
      float mn = tmin[tx], mx = tmax[tx];
      for (int x = x0; x < x1; ++x) {
        mn = std::min(mn, row[x]);
        mx = std::max(mx, row[x]);
      }
      tmin[tx] = mn;
      tmax[tx] = mx;
    }
  }
  // 2. Widen to the 3 x 3 tiles around each tile (separable).
  minmax3(s.tile_min, s.tile_max, s.tmp_min, s.tmp_max, tw, th, true);
  minmax3(s.tmp_min, s.tmp_max, s.tile_min, s.tile_max, tw, th, false);

  // 3. Class each pixel against its tile's midpoint.
  for (int y = 0; y < h; ++y) {
    const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    std::uint8_t* o = out.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const std::size_t trow = static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
    for (int tx = 0; tx < tw; ++tx) {
      const float mn = s.tile_min[trow + static_cast<std::size_t>(tx)], mx = s.tile_max[trow + static_cast<std::size_t>(tx)];
      const int x0 = tx * t, x1 = std::min(w, x0 + t);
      if (mx - mn < opt.min_contrast) {
        std::fill(o + x0, o + x1, kTernaryUnknown);
        continue;
      }
      const float mid = mn + 0.5f * (mx - mn);
      for (int x = x0; x < x1; ++x) o[x] = row[x] > mid ? kTernaryLight : kTernaryDark;
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
