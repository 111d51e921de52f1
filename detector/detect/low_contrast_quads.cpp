#include "detect/low_contrast_quads.hpp"

#include <algorithm>
#include <cmath>

#include "detect/outer_outline.hpp"

namespace tagbench {

void faint_regions(const ThresholdScratch& windows, int w, int h, int t, float low, float high,
                   const LowContrastPassOptions& opt, LowContrastScratch& s, std::vector<FaintRegion>& out) {
  out.clear();
  if (w < 1 || h < 1 || t < 1) return;
  const int tw = (w + t - 1) / t, th = (h + t - 1) / t;
  const std::size_t nt = static_cast<std::size_t>(tw) * static_cast<std::size_t>(th);
  if (windows.tile_min.size() < nt || windows.tile_max.size() < nt) return;
  // The band's tiles as the light class of a tile image (light is 8-connected), the rest unknown:
  // the threshold stage's run-based components label them.
  s.tiles.width = tw, s.tiles.height = th;
  s.tiles.data.resize(nt);
  // Through local pointers and branch-free: a byte store may alias the vectors' own pointers, which
  // the compiler would otherwise reload every tile.
  const float *tmax = windows.tile_max.data(), *tmin = windows.tile_min.data();
  std::uint8_t* tiles = s.tiles.data.data();
  static_assert(kTernaryLight == kTernaryUnknown + 128);
  for (std::size_t k = 0; k < nt; ++k) {
    const float d = tmax[k] - tmin[k];
    tiles[k] = static_cast<std::uint8_t>(kTernaryUnknown + (((d >= low) & (d < high)) << 7));
  }
  connected_components(s.tiles, s.tile_scratch, s.tile_components, false);
  // Each region's box over its runs. A component's id is its first run (the smallest index: the
  // union-find keeps the smaller root), so ids in increasing order are the regions in raster order
  // of their first tile.
  const Components& c = s.tile_components;
  s.boxes.resize(c.runs.size());
  for (int ty = 0; ty < th; ++ty)
    for (std::uint32_t i = c.row_start[static_cast<std::size_t>(ty)]; i < c.row_start[static_cast<std::size_t>(ty) + 1]; ++i) {
      const std::uint32_t id = c.run_label[i];
      if (id == kNoComponent) continue;
      FaintRegion& b = s.boxes[id];
      if (id == i) b = {c.runs[i].x0, ty, c.runs[i].x1, ty, 0};
      b.x0 = std::min(b.x0, c.runs[i].x0), b.x1 = std::max(b.x1, c.runs[i].x1), b.y1 = ty;
    }
  for (std::uint32_t i = 0; i < c.runs.size(); ++i) {
    if (c.run_label[i] != i) continue;
    const FaintRegion& r = s.boxes[i];
    const int bx0 = r.x0, bx1 = r.x1, by0 = r.y0, by1 = r.y1, count = static_cast<int>(c.size[i]);
    const int bw = bx1 - bx0 + 1, bh = by1 - by0 + 1;
    const double side = static_cast<double>(std::max(bw, bh) * t);
    if (side < opt.min_size_px || side > opt.max_size_px + 6.0 * t) continue;
    if (count < opt.min_fill * bw * bh || count * t * t < opt.min_area_px) continue;
    if (std::min(bw, bh) < opt.min_aspect * std::max(bw, bh)) continue;
    out.push_back({bx0 * t, by0 * t, std::min(w - 1, (bx1 + 1) * t - 1), std::min(h - 1, (by1 + 1) * t - 1), count});
  }
}

void low_contrast_quads(const ImageF& img, const ThresholdScratch& windows, const ThresholdOptions& threshold, bool dark_eight,
                        const BoundaryOptions& boundaries, const QuadFitOptions& fit, const LowContrastPassOptions& opt,
                        LowContrastScratch& s, QuadFitScratch& fit_scratch, std::vector<Quad>& out) {
  if (!opt.enabled || !(opt.min_contrast < threshold.min_contrast)) return;
  const int t = threshold.tile_size;
  faint_regions(windows, img.width, img.height, t, opt.min_contrast, threshold.min_contrast, opt, s, s.regions);
  ThresholdOptions low = threshold;
  low.min_contrast = opt.min_contrast;
  low.low_contrast = opt.min_contrast;  // the relative floor off: the low floor is absolute
  low.weber_ratio = 0;
  QuadFitOptions f = fit;
  f.tolerate_occlusion = f.tolerate_occlusion && opt.occlusion_fit;
  f.refit_outer_outline = f.refit_outer_outline && opt.outer_outline;
  OuterOutlineOptions ring = fit.outer;
  ring.ring_min_share = 1.0;
  for (const FaintRegion& r : s.regions) {
    const int m = static_cast<int>(std::ceil(opt.margin_px));
    const int x0 = std::max(0, r.x0 - m), y0 = std::max(0, r.y0 - m);
    const int x1 = std::min(img.width - 1, r.x1 + m), y1 = std::min(img.height - 1, r.y1 + m);
    s.crop.width = x1 - x0 + 1, s.crop.height = y1 - y0 + 1;  // storage reused from region to region
    s.crop.data.resize(static_cast<std::size_t>(s.crop.width) * static_cast<std::size_t>(s.crop.height));
    for (int y = y0; y <= y1; ++y)
      std::copy_n(img.data.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * img.width + x0),
                  s.crop.width, s.crop.data.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y - y0) * s.crop.width));
    adaptive_threshold(s.crop, low, s.pass.threshold, s.pass.ternary);
    connected_components(s.pass.ternary, s.pass.component_scratch, s.pass.components, dark_eight);
    group_boundaries(s.pass.ternary, s.pass.components, boundaries, s.pass.boundary_scratch, s.pass.groups);
    s.found.clear();
    fit_quads(s.pass.groups, s.crop, f, fit_scratch, s.found);
    for (Quad& q : s.found) {
      for (auto& p : q.corners) p += Eigen::Vector2d(x0, y0);
      if (opt.ring_check && !outline_has_ring(q.corners, img, ring)) continue;
      out.push_back(q);
    }
  }
}

}  // namespace tagbench
