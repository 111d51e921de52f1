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

// Min and max of each tile's share of one row, merged into tmin / tmax. T > 0: the tile size known
// at compile time; T == 0: `t` at run time.
template <int T>
void row_minmax(const float* row, int w, float* tmin, float* tmax, int t = T) {
  const int size = T > 0 ? T : t;
  const int full = w / size;
  for (int tx = 0; tx < full; ++tx) {
    const float* p = row + tx * size;
    float mn = tmin[tx], mx = tmax[tx];
    for (int i = 0; i < size; ++i) {
      mn = std::min(mn, p[i]);
      mx = std::max(mx, p[i]);
    }
    tmin[tx] = mn;
    tmax[tx] = mx;
  }
  if (full * size < w) {  // the partial last tile
    float mn = tmin[full], mx = tmax[full];
    for (int x = full * size; x < w; ++x) {
      mn = std::min(mn, row[x]);
      mx = std::max(mx, row[x]);
    }
    tmin[full] = mn;
    tmax[full] = mx;
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

  // 1. Tile min / max, one image row at a time (sequential reads; the common tile sizes get loops
  // the compiler unrolls).
  for (int y = 0; y < h; ++y) {
    const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    float* tmin = s.tile_min.data() + static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
    float* tmax = s.tile_max.data() + static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
    switch (t) {
      case 2: row_minmax<2>(row, w, tmin, tmax); break;
      case 3: row_minmax<3>(row, w, tmin, tmax); break;
      case 4: row_minmax<4>(row, w, tmin, tmax); break;
      default: row_minmax<0>(row, w, tmin, tmax, t); break;
    }
  }
  // 2. Widen to the 3 x 3 tiles around each tile (separable).
  minmax3(s.tile_min, s.tile_max, s.tmp_min, s.tmp_max, tw, th, true);
  minmax3(s.tmp_min, s.tmp_max, s.tile_min, s.tile_max, tw, th, false);

  // 3. Class each pixel against its tile's midpoint: per tile row, the midpoint of every column is
  // spread out once (a flat tile gets a midpoint above any intensity and is marked in `flat`), so the
  // per-pixel loop is branch-free.
  s.mid.resize(static_cast<std::size_t>(w));
  s.flat.resize(static_cast<std::size_t>(w));
  for (int y = 0; y < h; ++y) {
    if (y % t == 0) {
      const std::size_t trow = static_cast<std::size_t>(y / t) * static_cast<std::size_t>(tw);
      for (int x = 0; x < w; ++x) {
        const float mn = s.tile_min[trow + static_cast<std::size_t>(x / t)], mx = s.tile_max[trow + static_cast<std::size_t>(x / t)];
        const bool flat = mx - mn < opt.min_contrast;
        s.flat[static_cast<std::size_t>(x)] = flat ? kTernaryUnknown : 0;
        s.mid[static_cast<std::size_t>(x)] = mn + 0.5f * (mx - mn);
      }
    }
    const float* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    std::uint8_t* o = out.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const float* mid = s.mid.data();
    const std::uint8_t* flat = s.flat.data();
    for (int x = 0; x < w; ++x) {
      const std::uint8_t cls = row[x] > mid[x] ? kTernaryLight : kTernaryDark;
      o[x] = flat[x] ? kTernaryUnknown : cls;
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
