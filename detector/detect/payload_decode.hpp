#pragma once
// Reading the payload (paper section IV): sample every cell centre through the homography and
// threshold it against a spatially varying threshold learnt from the tag's border.
//
// Tag coordinates: the black square is [-1, 1]^2 (homography.hpp), so a cell is 2/(d+2) wide and
// grid cell g in 0..d+3 (0 = outer white ring, 1 = black ring, 2..d+1 = payload) has its centre at
// -1 + (g - 0.5) * 2/(d+2). The white ring's and the black ring's cells train two intensity models
//   I(x, y) = A x + B y + C x y + D      (the paper's equation (4), fit by least squares in tag coordinates;
//                                         with fewer than 6 samples a constant)
// and a payload cell is white (1) when its intensity exceeds the mean of the two models there.
// Intensities are bilinear samples of the decoding image (pixel centres at integer coordinates).
// The bits come out in AprilTag 1 order as seen through the quad: the MSB is the cell nearest the
// quad's first corner; the decoder's rotation then says which corner is the printed top-left.
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "../codes/bits.hpp"
#include "image.hpp"

namespace tagbench {

struct PayloadOptions {
  double min_contrast = 0.02;  // white minus black model at the tag centre, on [0, 1] intensities
  // Beyond the paper, for speed: apply border_contrast_plausible (below) to each quad before its
  // homography and payload are computed (decode_quads.hpp does; read_payload itself ignores this
  // field). A tag has its white ring brighter than its black ring by min_contrast at the middle of
  // at least 3 of its 4 sides (3, so that one occluded side still passes); most false quads fail
  // this 8-sample test.
  bool quick_reject = true;
};

struct PayloadReading {
  Code bits = 0;
  double margin = 0;    // min over payload cells of |I - threshold| / ((white - black) / 2), in [0, 1]
  double contrast = 0;  // white model minus black model at the tag centre
  // Beyond the paper, for soft decoding (soft_decode.hpp): each payload cell's signed confidence
  // (I - threshold) / ((white - black) / 2), row-major (the bits' order, MSB first).
  std::vector<float> confidence;
  // The sample points in image coordinates (for the debug pictures of the paper's Fig. 4).
  std::vector<Eigen::Vector2d> white_points, black_points, payload_points;
};

// The quick_reject test straight from a quad's corners, before any homography: each side's midpoint
// is pushed half a ring cell outward (white ring) and inward (black ring) from the quad's centre, an
// affine approximation that is plenty for a pre-filter. d is the payload width (the largest of the
// families tried: its ring cells are the thinnest, so the samples stay inside every family's rings).
bool border_contrast_plausible(const ImageF& img, const std::array<Eigen::Vector2d, 4>& corners, int d,
                               double min_contrast);

// The same test with slack, for a quad placed a pixel or two off (a printed square's inner square,
// printed_square.hpp, inherits the outer quad's error): per side the lightest of four samples 0.25 to
// 1 ring cell outward against the darkest of three 0.25 to 0.75 ring cell inward must differ by
// min_contrast, on at least min_sides sides (1..4). A sample outside the image fails its side.
bool border_contrast_plausible_with_slack(const ImageF& img, const std::array<Eigen::Vector2d, 4>& corners, int d,
                                          double min_contrast, int min_sides);

// The check before refining a candidate quad: border_contrast_plausible, or, with slack_sides > 0,
// the test with slack on that many sides (for quads placed a pixel or two off).
bool border_worth_refining(const ImageF& img, const std::array<Eigen::Vector2d, 4>& corners, int d,
                           double min_contrast, int slack_sides);

// Bilinear intensity at a sub-pixel point p inside [0, w-1] x [0, h-1] of a non-empty image (the
// caller has checked). Inline: edge refinement (edge_refine.hpp) takes thousands per quad.
inline float sample_bilinear_inside(const ImageF& img, const Eigen::Vector2d& p) {
  const int x0 = std::min(static_cast<int>(p.x()), std::max(0, img.width - 2));
  const int y0 = std::min(static_cast<int>(p.y()), std::max(0, img.height - 2));
  const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
  const double fx = p.x() - x0, fy = p.y() - y0;
  const double top = img.at(x0, y0) * (1 - fx) + img.at(x1, y0) * fx;
  const double bot = img.at(x0, y1) * (1 - fx) + img.at(x1, y1) * fx;
  return static_cast<float>(top * (1 - fy) + bot * fy);
}

#if defined(__SSE2__)
// sample_bilinear_inside at the two points (qx[0], qy[0]) and (qx[1], qy[1]) into out[0], out[1]: the
// same doubles in the same operations in each lane, so the same floats. img is at least 2 x 2 and
// both points lie in [0, w - 1] x [0, h - 1].
inline void sample_bilinear_inside_pair(const ImageF& img, __m128d qx, __m128d qy, float* out) {
  const int w = img.width, xmax = w - 2, ymax = img.height - 2;  // x0 <= w - 2, so x1 = x0 + 1
  alignas(16) std::int32_t ix[4], iy[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(ix), _mm_cvttpd_epi32(qx));  // truncation, as static_cast<int>
  _mm_store_si128(reinterpret_cast<__m128i*>(iy), _mm_cvttpd_epi32(qy));
  const int x0a = std::min(ix[0], xmax), x0b = std::min(ix[1], xmax);
  const int y0a = std::min(iy[0], ymax), y0b = std::min(iy[1], ymax);
  const float* ra = img.data.data() + static_cast<std::ptrdiff_t>(y0a) * w + x0a;
  const float* rb = img.data.data() + static_cast<std::ptrdiff_t>(y0b) * w + x0b;
  const __m128d v00 = _mm_set_pd(rb[0], ra[0]), v10 = _mm_set_pd(rb[1], ra[1]);
  const __m128d v01 = _mm_set_pd(rb[w], ra[w]), v11 = _mm_set_pd(rb[w + 1], ra[w + 1]);
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d fx = _mm_sub_pd(qx, _mm_set_pd(x0b, x0a)), fy = _mm_sub_pd(qy, _mm_set_pd(y0b, y0a));
  const __m128d gx = _mm_sub_pd(one, fx), gy = _mm_sub_pd(one, fy);
  const __m128d top = _mm_add_pd(_mm_mul_pd(v00, gx), _mm_mul_pd(v10, fx));
  const __m128d bot = _mm_add_pd(_mm_mul_pd(v01, gx), _mm_mul_pd(v11, fx));
  alignas(16) float v[4];
  _mm_store_ps(v, _mm_cvtpd_ps(_mm_add_pd(_mm_mul_pd(top, gy), _mm_mul_pd(bot, fy))));
  out[0] = v[0], out[1] = v[1];
}
#endif

// The same along a scan whose consecutive points mostly fall in the same 2 x 2 pixels (edge scans
// step a quarter pixel): the four pixels are read again only when the cell changes. The same value
// as sample_bilinear_inside (the same doubles in the same operations).
struct BilinearCell {
  int x0 = -1, y0 = -1;
  double v00 = 0, v10 = 0, v01 = 0, v11 = 0;
};
inline float sample_bilinear_inside(const ImageF& img, const Eigen::Vector2d& p, BilinearCell& c) {
  const int x0 = std::min(static_cast<int>(p.x()), std::max(0, img.width - 2));
  const int y0 = std::min(static_cast<int>(p.y()), std::max(0, img.height - 2));
  if (x0 != c.x0 || y0 != c.y0) {
    const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
    c = {x0, y0, img.at(x0, y0), img.at(x1, y0), img.at(x0, y1), img.at(x1, y1)};
  }
  const double fx = p.x() - x0, fy = p.y() - y0;
  const double top = c.v00 * (1 - fx) + c.v10 * fx;
  const double bot = c.v01 * (1 - fx) + c.v11 * fx;
  return static_cast<float>(top * (1 - fy) + bot * fy);
}

// Bilinear intensity at a sub-pixel point; nullopt outside [0, w-1] x [0, h-1].
inline std::optional<float> sample_bilinear(const ImageF& img, const Eigen::Vector2d& p) {
  if (img.empty() || !(p.x() >= 0) || !(p.y() >= 0) || p.x() > img.width - 1 || p.y() > img.height - 1)
    return std::nullopt;
  return sample_bilinear_inside(img, p);
}

// Reads a d x d payload (1 <= d <= kMaxPayloadWidth) through the homography H (tag square
// [-1,1]^2 -> image). nullopt when a payload cell falls outside the image, when the border gives
// no usable model, or when the black border is not darker than the white one by opt.min_contrast
// (opt.quick_reject plays no part here).
std::optional<PayloadReading> read_payload(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                           const PayloadOptions& opt = {}, bool keep_points = false);

// The decision every payload reader shares (read_payload, read_payload_area): `grid` holds an
// intensity per cell of the (d+4) x (d+4) grid, row-major (NaN where the cell left the image), from
// which the white and black ring cells train the two models; `payload` holds the d x d values the
// payload cells are judged by, row-major (the grid's own, or a sharpened copy). nullopt when a ring
// gives no model, the contrast is below min_contrast or a payload value is NaN. Points are left empty
// (add_sample_points fills them).
std::optional<PayloadReading> decide_cells(std::span<const double> grid, std::span<const double> payload, int d,
                                           double min_contrast);

// The image points of the cells `decide_cells` used: ring cells with a value, every payload cell.
// `map` takes tag coordinates to the image.
template <class Map>
void add_sample_points(std::span<const double> grid, int d, const Map& map, PayloadReading& r) {
  const int n = d + 4;
  const double cell = 2.0 / (d + 2);
  const auto centre = [&](int g) { return -1.0 + (g - 0.5) * cell; };
  for (int gy = 0; gy < n; ++gy)
    for (int gx = 0; gx < n; ++gx) {
      const int ring = std::min({gx, gy, n - 1 - gx, n - 1 - gy});
      if (ring >= 2 || std::isnan(grid[static_cast<std::size_t>(gy * n + gx)])) continue;
      (ring == 0 ? r.white_points : r.black_points).push_back(map(Eigen::Vector2d(centre(gx), centre(gy))));
    }
  for (int y = 0; y < d; ++y)
    for (int x = 0; x < d; ++x) r.payload_points.push_back(map(Eigen::Vector2d(centre(x + 2), centre(y + 2))));
}

}  // namespace tagbench
