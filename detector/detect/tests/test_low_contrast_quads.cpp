#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "detect/homography.hpp"
#include "detect/low_contrast_quads.hpp"
#include "detect/threshold_quads.hpp"

namespace test_low_contrast_quads {

using namespace tagbench;

namespace {
// A flat ground with dark squares of pixels [x0, x0 + n) x [y0, y0 + n): `faint` 14 grey levels below
// the ground (under the main floor of 20/255, over the low floor of 10/255) and `bold` 120 below.
constexpr float kGround = 0.6f;
void square(ImageF& img, int x0, int y0, int n, float v) {
  for (int y = y0; y < y0 + n; ++y)
    for (int x = x0; x < x0 + n; ++x) img.at(x, y) = v;
}
ImageF scene() {
  ImageF img(120, 80, kGround);
  square(img, 20, 20, 20, kGround - 14.0f / 255);  // faint: edges at 19.5 and 39.5
  square(img, 70, 20, 20, kGround - 120.0f / 255);  // bold
  return img;
}
double worst_corner_error(const Corners& found, const Corners& want) {
  double best = HUGE_VAL;
  for (int s = 0; s < 4; ++s) best = std::min(best, max_corner_distance(want, found, s));
  return best;
}
Corners box(double lo_x, double lo_y, double hi_x, double hi_y) {
  return {Eigen::Vector2d(lo_x, lo_y), Eigen::Vector2d(hi_x, lo_y), Eigen::Vector2d(hi_x, hi_y), Eigen::Vector2d(lo_x, hi_y)};
}
std::vector<FaintRegion> regions_of(const ImageF& img, const LowContrastPassOptions& opt) {
  ThresholdOptions th;
  ThresholdScratch ts;
  TernaryImage t;
  adaptive_threshold(img, th, ts, t);
  LowContrastScratch s;
  std::vector<FaintRegion> out;
  faint_regions(ts, img.width, img.height, th.tile_size, opt.min_contrast, th.min_contrast, opt, s, out);
  return out;
}
}  // namespace

// Only the faint square's edge tiles are in the band; the bold square's window spans more than the main floor.
TEST(LowContrastQuads, FaintRegionIsTheFaintSquaresEdgeOnly) {
  const auto regions = regions_of(scene(), LowContrastPassOptions{});
  ASSERT_EQ(regions.size(), 1u);
  const FaintRegion& r = regions[0];
  EXPECT_LE(r.x0, 19);
  EXPECT_GE(r.x1, 40);
  EXPECT_GE(r.x0, 14);
  EXPECT_LE(r.x1, 46);
  EXPECT_LE(r.y0, 19);
  EXPECT_GE(r.y1, 40);
  EXPECT_GT(r.tiles, 0);
}

TEST(LowContrastQuads, RegionFiltersDropLargeSmallAndSparseRegions) {
  LowContrastPassOptions opt;
  opt.max_size_px = 10;  // + 2 windows (12 px) is still below the region's ~26 px
  EXPECT_TRUE(regions_of(scene(), opt).empty());
  opt = LowContrastPassOptions{};
  opt.min_size_px = 40;
  EXPECT_TRUE(regions_of(scene(), opt).empty());
  opt = LowContrastPassOptions{};
  opt.min_fill = 0.95;  // a square's edge tiles: a ring, its box far from filled
  EXPECT_TRUE(regions_of(scene(), opt).empty());
  // A faint one-pixel line 30 px long: a thin region (box 34 x 6 px), under min_aspect.
  ImageF line(120, 80, kGround);
  for (int x = 20; x < 50; ++x) line.at(x, 40) = kGround - 14.0f / 255;
  EXPECT_TRUE(regions_of(line, LowContrastPassOptions{}).empty());
  LowContrastPassOptions any;
  any.min_aspect = 0, any.min_area_px = 0;
  EXPECT_EQ(regions_of(line, any).size(), 1u);
}

// The regions are the 8-connected sets of band tiles a flood fill finds, in raster order of their
// first tile, with their boxes and tile counts: random tile spans, every filter loosened or not.
TEST(LowContrastQuads, FaintRegionsMatchAFloodFill) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 300; ++trial) {
    const int t = 1 + static_cast<int>(rng() % 4), w = 1 + static_cast<int>(rng() % 90), h = 1 + static_cast<int>(rng() % 70);
    const int tw = (w + t - 1) / t, th = (h + t - 1) / t;
    ThresholdScratch ts;
    ts.tile_min.assign(static_cast<std::size_t>(tw * th), 0.0f);
    ts.tile_max.resize(ts.tile_min.size());
    const int density = 1 + static_cast<int>(rng() % 9);
    for (auto& v : ts.tile_max) v = static_cast<int>(rng() % 10) < density ? 0.05f : (rng() % 2 ? 0.01f : 0.5f);
    LowContrastPassOptions opt;
    if (trial % 2) opt.min_size_px = 0, opt.max_size_px = 1e9, opt.min_fill = 0, opt.min_area_px = 0, opt.min_aspect = 0;
    LowContrastScratch s;
    std::vector<FaintRegion> got;
    faint_regions(ts, w, h, t, 0.02f, 0.1f, opt, s, got);
    // The reference: a flood fill from each band tile in raster order, the same filters.
    std::vector<int> seen(static_cast<std::size_t>(tw * th), 0);
    const auto band = [&](int k) { return ts.tile_max[static_cast<std::size_t>(k)] == 0.05f; };
    std::vector<FaintRegion> want;
    for (int k0 = 0; k0 < tw * th; ++k0) {
      if (!band(k0) || seen[static_cast<std::size_t>(k0)]) continue;
      int bx0 = k0 % tw, bx1 = bx0, by0 = k0 / tw, by1 = by0, count = 0;
      std::vector<int> stack = {k0};
      seen[static_cast<std::size_t>(k0)] = 1;
      while (!stack.empty()) {
        const int k = stack.back();
        stack.pop_back();
        const int x = k % tw, y = k / tw;
        ++count;
        bx0 = std::min(bx0, x), bx1 = std::max(bx1, x), by0 = std::min(by0, y), by1 = std::max(by1, y);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy, n = ny * tw + nx;
            if (nx < 0 || ny < 0 || nx >= tw || ny >= th || !band(n) || seen[static_cast<std::size_t>(n)]) continue;
            seen[static_cast<std::size_t>(n)] = 1;
            stack.push_back(n);
          }
      }
      const int bw = bx1 - bx0 + 1, bh = by1 - by0 + 1;
      const double side = static_cast<double>(std::max(bw, bh) * t);
      if (side < opt.min_size_px || side > opt.max_size_px + 6.0 * t) continue;
      if (count < opt.min_fill * bw * bh || count * t * t < opt.min_area_px) continue;
      if (std::min(bw, bh) < opt.min_aspect * std::max(bw, bh)) continue;
      want.push_back({bx0 * t, by0 * t, std::min(w - 1, (bx1 + 1) * t - 1), std::min(h - 1, (by1 + 1) * t - 1), count});
    }
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].x0, want[i].x0);
      EXPECT_EQ(got[i].y0, want[i].y0);
      EXPECT_EQ(got[i].x1, want[i].x1);
      EXPECT_EQ(got[i].y1, want[i].y1);
      EXPECT_EQ(got[i].tiles, want[i].tiles) << "trial " << trial << " region " << i;
    }
  }
}

TEST(LowContrastQuads, FindsTheFaintSquareTheMainPassMisses) {
  const ImageF img = scene();
  ThresholdQuadOptions tq;
  tq.refine_edges = false;
  ThresholdQuadWorkspace ws;
  std::vector<Quad> main;
  find_threshold_quads(img, tq, ws, main);
  const Corners faint = box(19.5, 19.5, 39.5, 39.5), bold = box(69.5, 19.5, 89.5, 39.5);
  for (const Quad& q : main) EXPECT_GT(worst_corner_error(q.corners, faint), 3.0);  // no quad on the faint one
  LowContrastPassOptions opt;
  opt.enabled = true;
  std::vector<Quad> low;
  QuadFitScratch fs;
  low_contrast_quads(img, ws.pass.threshold, tq.threshold, tq.dark_eight_connected, tq.boundaries, tq.fit, opt,
                     ws.low_contrast, fs, low);
  ASSERT_EQ(low.size(), 1u);
  EXPECT_LT(worst_corner_error(low[0].corners, faint), 0.3);
  // The stage with the pass on: the bold square's quad and the faint one's.
  tq.low_contrast.enabled = true;
  std::vector<Quad> both;
  find_threshold_quads(img, tq, ws, both);
  ASSERT_EQ(both.size(), main.size() + 1);
  double e_faint = HUGE_VAL, e_bold = HUGE_VAL;
  for (const Quad& q : both)
    e_faint = std::min(e_faint, worst_corner_error(q.corners, faint)), e_bold = std::min(e_bold, worst_corner_error(q.corners, bold));
  EXPECT_LT(e_faint, 0.3);
  EXPECT_LT(e_bold, 0.3);
}

TEST(LowContrastQuads, OffOrFloorNotBelowTheMainOneFindsNothing) {
  const ImageF img = scene();
  ThresholdQuadOptions tq;
  ThresholdQuadWorkspace ws;
  std::vector<Quad> main;
  find_threshold_quads(img, tq, ws, main);
  LowContrastPassOptions opt;  // enabled = false
  std::vector<Quad> low;
  QuadFitScratch fs;
  low_contrast_quads(img, ws.pass.threshold, tq.threshold, tq.dark_eight_connected, tq.boundaries, tq.fit, opt,
                     ws.low_contrast, fs, low);
  EXPECT_TRUE(low.empty());
  opt.enabled = true;
  opt.min_contrast = tq.threshold.min_contrast;
  low_contrast_quads(img, ws.pass.threshold, tq.threshold, tq.dark_eight_connected, tq.boundaries, tq.fit, opt,
                     ws.low_contrast, fs, low);
  EXPECT_TRUE(low.empty());
}

// A faint dark square inside a darker patch is found (the patch is its lighter ring); a faint LIGHT
// square gives no quad (dark inside only, and no lighter ring).
TEST(LowContrastQuads, FindsFaintDarkSquaresNotLightOnes) {
  ImageF img(80, 80, kGround);
  square(img, 20, 20, 30, kGround - 30.0f / 255);    // a darker patch, 30 px
  square(img, 25, 25, 20, kGround - 42.0f / 255);    // a faint square 12 levels darker inside it
  // The patch's own edge is bold (30 levels: the main pass); the inner square's is faint.
  ThresholdQuadOptions tq;
  ThresholdQuadWorkspace ws;
  std::vector<Quad> main;
  find_threshold_quads(img, tq, ws, main);
  LowContrastPassOptions opt;
  opt.enabled = true;
  std::vector<Quad> low;
  QuadFitScratch fs;
  low_contrast_quads(img, ws.pass.threshold, tq.threshold, tq.dark_eight_connected, tq.boundaries, tq.fit, opt,
                     ws.low_contrast, fs, low);
  const Corners inner = box(24.5, 24.5, 44.5, 44.5);
  double e = HUGE_VAL;
  for (const Quad& q : low) e = std::min(e, worst_corner_error(q.corners, inner));
  EXPECT_LT(e, 0.5);
  // ...and a faint LIGHT square (lighter than its ground) gives no quad.
  ImageF light(80, 80, kGround);
  square(light, 25, 25, 20, kGround + 14.0f / 255);
  find_threshold_quads(light, tq, ws, main);
  low.clear();
  low_contrast_quads(light, ws.pass.threshold, tq.threshold, tq.dark_eight_connected, tq.boundaries, tq.fit, opt,
                     ws.low_contrast, fs, low);
  EXPECT_TRUE(low.empty());
}

}  // namespace test_low_contrast_quads
