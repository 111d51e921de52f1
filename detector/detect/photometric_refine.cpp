#include "detect/photometric_refine.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "detect/detector.hpp"
#include "detect/photometric_model.hpp"

namespace tagbench {
namespace {

using detail::kPhotometricSigma;
using detail::PhotometricMat;
using detail::PhotometricPattern;
using detail::PhotometricVec;

struct Pixel {
  float xn, yn;  // normalised image coordinates
  float value;
};

// One row of the pixel selection: candidate columns and their per-pixel values.
struct RowScratch {
  std::vector<int> x, ok;
  std::vector<float> xn, w, u1, u2, b1, b2, d1, d2;
  void resize(int m) {
    const auto k = static_cast<std::size_t>(m);
    ok.resize(k), xn.resize(k), w.resize(k), u1.resize(k), u2.resize(k), b1.resize(k), b2.resize(k), d1.resize(k), d2.resize(k);
  }
};

Eigen::Vector2d map(const Eigen::Matrix3d& M, double x, double y) {
  const Eigen::Vector3d q = M * Eigen::Vector3d(x, y, 1);
  return q.head<2>() / q.z();
}

}  // namespace

struct PhotometricWorkspace::Impl {
  RowScratch rows;
  std::vector<std::uint8_t> skip;
  std::vector<Pixel> px, keep;
  detail::PhotometricSamples samples;
  std::vector<float> values;  // the samples' intensities, partly sorted for the start levels
  detail::PhotometricScratch model;
};

PhotometricWorkspace::PhotometricWorkspace() : impl(std::make_unique<Impl>()) {}
PhotometricWorkspace::~PhotometricWorkspace() = default;
PhotometricWorkspace::PhotometricWorkspace(PhotometricWorkspace&&) noexcept = default;
PhotometricWorkspace& PhotometricWorkspace::operator=(PhotometricWorkspace&&) noexcept = default;

std::optional<Corners> refine_corners_photometric(const ImageF& img, const TagCells& cells, const Corners& corners,
                                                  const PhotometricRefineOptions& opt, std::span<const TagBox> excluded,
                                                  PhotometricWorkspace* workspace) {
  std::optional<PhotometricWorkspace> local;  // only without a caller's workspace
  PhotometricWorkspace& ws = workspace ? *workspace : local.emplace();
  if (!ws.impl) ws.impl = std::make_unique<PhotometricWorkspace::Impl>();  // a moved-from one
  PhotometricWorkspace::Impl& w = *ws.impl;
  if (img.empty() || cells.n < 5 || !(opt.gamma > 0 && std::isfinite(opt.gamma))) return std::nullopt;
  const auto H = tag_homography(corners);
  if (!H) return std::nullopt;
  const double side = perimeter(corners) / 4;
  if (!(side >= opt.min_black_square_px)) return std::nullopt;

  // Normalised image coordinates x' = (x - c) / S, for a well-conditioned G (x' -> u) with G33 = 1.
  const Eigen::Vector2d c0 = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  const double S = side / 2;
  Eigen::Matrix3d Ninv;
  Ninv << S, 0, c0.x(), 0, S, c0.y(), 0, 0, 1;
  Eigen::Matrix3d G = H->inverse() * Ninv;
  if (!(std::abs(G(2, 2)) > 1e-12)) return std::nullopt;
  G /= G(2, 2);

  const PhotometricPattern pat(cells);
  const double reach = 1 + opt.margin_cells * pat.cell;

  // The pixels near a transition of the pattern, inside the reach.
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  std::array<Eigen::Vector2d, 4> foot;  // the reach square's image
  bool convex_view = true;              // all of it in front of the camera: a convex quad
  {
    const double wc = (*H)(2, 2);
    std::size_t k = 0;
    for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
      const Eigen::Vector3d h = *H * Eigen::Vector3d(sx * reach, sy * reach, 1);
      convex_view = convex_view && h.z() * wc > 0;
      const Eigen::Vector2d q = foot[k++] = map(*H, sx * reach, sy * reach);
      x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
    }
  }
  const int ix0 = std::max(0, static_cast<int>(std::ceil(x0))), ix1 = std::min(img.width - 1, static_cast<int>(std::floor(x1)));
  const int iy0 = std::max(0, static_cast<int>(std::ceil(y0))), iy1 = std::min(img.height - 1, static_cast<int>(std::floor(y1)));
  // A large tag is sampled on a coarser grid (every stride-th pixel each way) so that the transition
  // bands hold about 2 x max_pixels: the band is about a fifth of the tag's area at 8 cells across.
  const int budget = std::max(opt.max_pixels, static_cast<int>(std::min(1e7, opt.pixels_per_side_px * side)));
  const double area = std::max(0.0, (x1 - x0) * (y1 - y0));
  const int stride = std::max(1, static_cast<int>(std::sqrt(area * 0.4 / (2.0 * budget))));
  // Blocks of kBlock x kBlock pixels none of whose pixels can pass the tests below are skipped whole
  // (most of a large tag's area: the cells' insides). Exact, not a heuristic: G maps the block to the
  // convex hull of its corners' images (w > 0 there), so the corners give the range of u1 and u2
  // over it; the band is largest where |e| (convex in u) and 1 / w (w affine) are, at the ends.
  // If the cells over the ranges widened by the largest band are all one colour (or the block is
  // past the reach), no pixel of it is near a transition. Small tags' cells are too small for this.
  constexpr int kBlock = 8;
  const bool blocks = side / (cells.n - 2) >= 2 * kBlock;
  const int bw = (ix1 - ix0) / kBlock + 1;
  std::vector<std::uint8_t>& skip = w.skip;
  skip.assign(blocks && ix1 >= ix0 && iy1 >= iy0 ? static_cast<std::size_t>(bw * ((iy1 - iy0) / kBlock + 1)) : 0, 0);
  for (std::size_t b = 0; b < skip.size(); ++b) {
    const int bx = ix0 + static_cast<int>(b) % bw * kBlock, by = iy0 + static_cast<int>(b) / bw * kBlock;
    double lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY, wmin = INFINITY;
    for (const auto& [x, y] : {std::pair{bx, by}, {std::min(bx + kBlock - 1, ix1), by}, {bx, std::min(by + kBlock - 1, iy1)},
                               {std::min(bx + kBlock - 1, ix1), std::min(by + kBlock - 1, iy1)}}) {
      const double xn = (x - c0.x()) / S, yn = (y - c0.y()) / S;
      const double w = G(2, 0) * xn + G(2, 1) * yn + 1;
      const double u1 = (G(0, 0) * xn + G(0, 1) * yn + G(0, 2)) / w, u2 = (G(1, 0) * xn + G(1, 1) * yn + G(1, 2)) / w;
      wmin = std::min(wmin, w);
      lo1 = std::min(lo1, u1), hi1 = std::max(hi1, u1), lo2 = std::min(lo2, u2), hi2 = std::max(hi2, u2);
    }
    if (!(wmin > 1e-6)) continue;
    constexpr double eps = 1e-5;  // rounding between this and the pixels' (single-precision) arithmetic
    if (lo1 > reach + eps || hi1 < -reach - eps || lo2 > reach + eps || hi2 < -reach - eps) {
      skip[b] = 1;
      continue;
    }
    const auto band = [&](int row, double u) { return std::hypot(G(row, 0) - u * G(2, 0), G(row, 1) - u * G(2, 1)); };
    const double b1 = opt.band_px * std::max(band(0, lo1), band(0, hi1)) / (wmin * S) + eps;
    const double b2 = opt.band_px * std::max(band(1, lo2), band(1, hi2)) / (wmin * S) + eps;
    const int cx0 = pat.index(lo1 - b1), cx1 = pat.index(hi1 + b1), cy0 = pat.index(lo2 - b2), cy1 = pat.index(hi2 + b2);
    const bool v = pat.white(cy0, cx0);
    bool uniform = true;
    for (int cy = cy0; cy <= cy1 && uniform; ++cy)
      for (int cx = cx0; cx <= cx1 && uniform; ++cx) uniform = pat.white(cy, cx) == v;
    skip[b] = uniform;
  }
  // Each row from a pixel before the reach's image to one after it (the pixels further out map
  // past the reach; a rotated tag's bounding box is up to twice its area).
  const auto row_span = [&](int y, int& xa, int& xb) {
    xa = ix0, xb = ix1;
    if (!convex_view) return;
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t k = 0; k < 4; ++k) {
      const Eigen::Vector2d &a = foot[k], &b = foot[(k + 1) % 4];
      if (y < std::min(a.y(), b.y()) || y > std::max(a.y(), b.y())) continue;
      const double x = a.y() == b.y() ? a.x() : a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      lo = std::min({lo, x, a.y() == b.y() ? b.x() : x}), hi = std::max({hi, x, a.y() == b.y() ? b.x() : x});
    }
    if (!(lo <= hi)) return;
    xa = std::max(ix0, static_cast<int>(std::ceil(lo - 1))), xb = std::min(ix1, static_cast<int>(std::floor(hi + 1)));
  };
  // Per row, the pixels' tag coordinates and bands in single precision over arrays (plain loops the
  // compiler vectorises), then, for those near a grid line, the pattern: a cell within the band
  // either way (3 columns and 3 rows) differs from the pixel's own. When the band is under a cell
  // (so the 3 columns/rows are the pixel's cell and its neighbours) that is one mask test on the
  // cell's neighbourhood bits.
  RowScratch& r = w.rows;
  r.resize(ix1 >= ix0 ? (ix1 - ix0) / stride + 1 : 0);  // the widest row: no resize per row
  r.x.reserve(r.ok.size());
  std::vector<Pixel>& px = w.px;
  px.clear();
  const float fS = static_cast<float>(S), fcx = static_cast<float>(c0.x()), band_s = static_cast<float>(opt.band_px / S);
  const float g00 = static_cast<float>(G(0, 0)), g01 = static_cast<float>(G(0, 1)), g10 = static_cast<float>(G(1, 0)),
              g11 = static_cast<float>(G(1, 1)), g20 = static_cast<float>(G(2, 0)), g21 = static_cast<float>(G(2, 1));
  const float freach = static_cast<float>(reach), cell = static_cast<float>(pat.cell), inv_cell = 1 / cell;
  const int stride_n = pat.n + 2, n = pat.n;
  for (int y = iy0; y <= iy1; y += stride) {
    int xa, xb;
    row_span(y, xa, xb);
    int xs = ix0 + (y / stride) % stride;  // the row's lattice: xs + k stride
    if (xa > xs) xs += (xa - xs + stride - 1) / stride * stride;
    r.x.clear();
    for (int x = xs; x <= xb; x += stride) {
      if (!skip.empty() && skip[static_cast<std::size_t>((y - iy0) / kBlock * bw + (x - ix0) / kBlock)]) {
        // On to the block's first pixel column on this row's lattice (x = ix0 + offset + k stride).
        const int next = ix0 + ((x - ix0) / kBlock + 1) * kBlock;
        x += (next - x + stride - 1) / stride * stride - stride;
        continue;
      }
      r.x.push_back(x);
    }
    const int m = static_cast<int>(r.x.size());
    const float yn = static_cast<float>((y - c0.y()) / S);
    const float aw = static_cast<float>(G(2, 1) * yn + 1), a1 = static_cast<float>(G(0, 1) * yn + G(0, 2)),
                a2 = static_cast<float>(G(1, 1) * yn + G(1, 2));
    const int* rx = r.x.data();
    // Eigen's packets for the arithmetic (its sqrt vectorises under any flags; std::sqrt only because the
    // library is built with -fno-math-errno, detector/CMakeLists.txt).
    using FMap = Eigen::Map<Eigen::ArrayXf>;
    FMap xn(r.xn.data(), m), w(r.w.data(), m), u1(r.u1.data(), m), u2(r.u2.data(), m), b1(r.b1.data(), m), b2(r.b2.data(), m);
    xn = (Eigen::Map<const Eigen::ArrayXi>(rx, m).cast<float>() - fcx) / fS;
    w = g20 * xn + aw;
    b2 = w.inverse();  // 1 / w until the last line
    u1 = (g00 * xn + a1) * b2;
    u2 = (g10 * xn + a2) * b2;
    b1 = band_s * ((g00 - u1 * g20).square() + (g01 - u1 * g21).square()).sqrt() * b2;
    b2 = band_s * ((g10 - u2 * g20).square() + (g11 - u2 * g21).square()).sqrt() * b2;
    // Distance to the nearest grid line, per axis (clamped first: outside the reach it is not used).
    FMap d1(r.d1.data(), m), d2(r.d2.data(), m);
    d1 = ((u1 + 1.0f) * inv_cell).max(-32.0f).min(32.0f) + 64.5f;
    d1 = (d1 - d1.cast<int>().cast<float>() - 0.5f).abs() * cell;
    d2 = ((u2 + 1.0f) * inv_cell).max(-32.0f).min(32.0f) + 64.5f;
    d2 = (d2 - d2.cast<int>().cast<float>() - 0.5f).abs() * cell;
    Eigen::Map<Eigen::ArrayXi>(r.ok.data(), m) =
        ((w > 1e-9f) && (u1.abs() <= freach) && (u2.abs() <= freach) && ((d1 <= b1) || (d2 <= b2))).cast<int>();
    const float *xn_ = r.xn.data(), *u1_ = r.u1.data(), *u2_ = r.u2.data(), *b1_ = r.b1.data(), *b2_ = r.b2.data();
    const int* ok_ = r.ok.data();
    const auto index = [&](float u) { return std::clamp(static_cast<int>((u + 1) * inv_cell + 64) - 63, -1, n); };
    for (int k = 0; k < m; ++k) {
      if (!ok_[k]) continue;
      const float u1 = u1_[k], u2 = u2_[k], b1 = b1_[k], b2 = b2_[k];
      const int cx[3] = {index(u1 - b1), index(u1), index(u1 + b1)};
      const int cy[3] = {index(u2 - b2), index(u2), index(u2 + b2)};
      bool edge = false;
      if (cx[1] - cx[0] <= 1 && cx[2] - cx[1] <= 1 && cy[1] - cy[0] <= 1 && cy[2] - cy[1] <= 1) {
        const unsigned bits = pat.neighbours[static_cast<std::size_t>((cy[1] + 1) * stride_n + cx[1] + 1)];
        const unsigned cols = 2u | (cx[0] < cx[1] ? 1u : 0u) | (cx[2] > cx[1] ? 4u : 0u);
        unsigned sel = cols << 3;
        if (cy[0] < cy[1]) sel |= cols;
        if (cy[2] > cy[1]) sel |= cols << 6;
        edge = ((bits ^ ((bits >> 4) & 1u ? 0x1FFu : 0u)) & sel) != 0;
      } else {
        const bool v0 = pat.white(cy[1], cx[1]);
        for (int j = 0; j < 3 && !edge; ++j)
          for (int i = 0; i < 3 && !edge; ++i) edge = pat.white(cy[j], cx[i]) != v0;
      }
      if (edge && !excluded.empty() && std::any_of(excluded.begin(), excluded.end(), [&](const TagBox& b) {
            return u1 >= b.u1_lo && u1 <= b.u1_hi && u2 >= b.u2_lo && u2 <= b.u2_hi;
          }))
        edge = false;
      if (edge) px.push_back({xn_[k], yn, linearised(img.at(rx[k], y), opt.gamma)});
    }
  }
  if (static_cast<int>(px.size()) < opt.min_pixels) return std::nullopt;
  if (static_cast<int>(px.size()) > budget) {  // evenly spread subsample
    const double step = static_cast<double>(px.size()) / budget;
    std::vector<Pixel>& keep = w.keep;
    keep.clear();
    keep.reserve(static_cast<std::size_t>(budget));
    for (int k = 0; k < budget; ++k) keep.push_back(px[static_cast<std::size_t>(k * step)]);
    px.swap(keep);
  }
  // Filled by index, not push_back (which the compiler keeps a call: a fifth of this function's own cost).
  detail::PhotometricSamples& samples = w.samples;
  samples.xn.resize(px.size()), samples.yn.resize(px.size()), samples.value.resize(px.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    samples.xn[i] = px[i].xn, samples.yn[i] = px[i].yn, samples.value[i] = px[i].value;

  // Start: black and white levels from the pixels' 10th and 90th percentiles, no shading.
  std::vector<float>& v = w.values;
  v.assign(samples.value.begin(), samples.value.end());
  const auto lo = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 10), hi = v.begin() + static_cast<std::ptrdiff_t>(v.size() * 9 / 10);
  std::nth_element(v.begin(), lo, v.end());
  const double black = *lo;
  std::nth_element(v.begin(), hi, v.end());
  const double white = *hi;
  if (!(white - black >= opt.min_contrast)) return std::nullopt;
  PhotometricVec p;
  p << G(0, 0), G(0, 1), G(0, 2), G(1, 0), G(1, 1), G(1, 2), G(2, 0), G(2, 1), black, 0, 0, white - black, 0, 0,
      opt.initial_blur_px;
  // Huber threshold: a fraction of the contrast (so noise-free model mismatch at the edges counts in
  // full and an occluder's or glare's pixels with a bounded weight).
  const double huber = opt.huber * (white - black);
  PhotometricMat JtJ;
  PhotometricVec Jtr;
  detail::PhotometricScratch& scratch = w.model;
  // Gauss-Newton steps, one pass over the pixels each: a step whose pass shows a higher cost than the
  // previous one is taken back and the fit stops there. The last step is taken on trust (no pass of
  // its own: the start is within a few hundredths of a pixel, where the model is nearly linear in the
  // geometry), bounded by max_corner_shift_px and the contrast check below.
  double cost = detail::photometric_normal_equations(pat, samples, S, p, huber, JtJ, Jtr, scratch, opt.column_dot_sums);
  for (int it = 0; it < opt.iterations; ++it) {
    PhotometricMat A = JtJ;
    A.diagonal() += 1e-6 * JtJ.diagonal().cwiseMax(1e-12);  // a touch of damping against a flat direction
    const PhotometricVec d = A.ldlt().solve(Jtr);
    if (!d.allFinite()) return std::nullopt;
    PhotometricVec q = p + d;
    q(kPhotometricSigma) = std::clamp(q(kPhotometricSigma), 0.1, 8.0);
    if (it + 1 == opt.iterations) {
      p = q;
      break;
    }
    const double c = detail::photometric_normal_equations(pat, samples, S, q, huber, JtJ, Jtr, scratch, opt.column_dot_sums);
    if (!(c <= cost)) break;  // p stays
    p = q, cost = c;
  }
  if (!(p(11) >= opt.min_contrast) || !(p(kPhotometricSigma) <= opt.max_blur_cells * side / (cells.n - 2))) return std::nullopt;

  Eigen::Matrix3d Gr;
  Gr << p(0), p(1), p(2), p(3), p(4), p(5), p(6), p(7), 1;
  const Eigen::Matrix3d Hr = Ninv * Gr.inverse();
  Corners out;
  const std::array<Eigen::Vector2d, 4> tag{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                           Eigen::Vector2d(-1, 1)};
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = map(Hr, tag[i].x(), tag[i].y());
    if (!out[i].allFinite() || (out[i] - corners[i]).norm() > opt.max_corner_shift_px) return std::nullopt;
  }
  return out;
}

bool move_detection_to(Detection& d, const std::optional<Corners>& corners) {
  const auto H = corners ? tag_homography(*corners) : std::nullopt;
  if (!H) return false;
  d.corners = *corners;
  d.homography = *H;
  d.center = apply_homography(*H, Eigen::Vector2d::Zero());
  return true;
}

void refine_detections_photometric(std::span<Detection> detections, const ImageF& img,
                                   std::span<const TagFamily> families, const PhotometricRefineOptions& opt,
                                   PhotometricWorkspace* workspace) {
  for (Detection& d : detections)
    for (const TagFamily& f : families) {
      if (f.name() != d.family) continue;
      move_detection_to(d, refine_corners_photometric(img, tag_cells(f, d.id), d.corners, opt, {}, workspace));
      break;
    }
}

}  // namespace tagbench
