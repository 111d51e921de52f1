#pragma once
// Low-pass filtering and 2x decimation before segmentation (paper section III-A; segSigma = 0.8,
// segDecimate: docs/paper-to-code.md section 1).
//
// Conventions (see image.hpp): pixel centres at integer coordinates, x right, y down.
//
// Gaussian blur: separable, kernel g[i] proportional to exp(-i^2 / (2 sigma^2)) for
// i = -r..r with radius r = ceil(3 sigma) (so the truncated tails hold < 0.3 % of the mass),
// normalised to sum 1 so constant images stay constant. Borders are handled by clamping:
// samples outside the image read the nearest edge pixel.
//
// Decimation: half_resolution averages 2x2 blocks. Half-resolution pixel X is the mean of full
// pixels 2X and 2X+1, whose centres are at 2X and 2X+1, so its centre sits at full-resolution
// coordinate 2X + 0.5: x_full = full_from_half(x_half) = 2 x_half + 0.5 (same for y), and
// lengths double. An odd last row or column is dropped (the output is floor(w/2) x floor(h/2)).
#include <cstdint>
#include <span>
#include <vector>

#include "detect/image.hpp"

namespace tagbench {

// The paper's recommended blur for segmentation (paper section III-A; docs/paper-to-code.md section 1).
inline constexpr double kSegSigma = 0.8;

// Kernel radius ceil(3 sigma); 0 for sigma <= 0.
int gaussian_radius(double sigma);

// The normalised 1-D kernel, 2 r + 1 taps, centre tap at index r. {1} for sigma <= 0.
std::vector<float> gaussian_kernel(double sigma);

// Separable Gaussian blur with clamped borders. sigma <= 0 is "off" and returns the input unchanged.
ImageF gaussian_blur(const ImageF& img, double sigma);

// 2x2 block-average decimation to floor(w/2) x floor(h/2).
ImageF half_resolution(const ImageF& img);

// Maps a half-resolution coordinate (x or y) to full resolution: 2 x_half + 0.5.
constexpr double full_from_half(double x_half) { return 2.0 * x_half + 0.5; }

// half_resolution(gaussian_blur(img, sigma)) computed in one pass pair: the 2x2 box is folded into
// the Gaussian (a 2 r + 2 tap kernel) and evaluated only at the even positions that survive the
// decimation, so it costs about a third of blurring at full resolution. Equal to the two-step
// result up to float rounding, borders included. sigma <= 0 gives half_resolution(img).
ImageF blur_and_halve(const ImageF& img, double sigma);

// The same three filters writing into caller-owned images, for the detector's workspace
// (detector.hpp): `out` and the scratch image `tmp` are resized, which keeps their storage, so
// frames of one size reuse it. Results are identical to the functions above. `out` and `tmp`
// must be distinct objects and must not be `img`.
void gaussian_blur(const ImageF& img, double sigma, ImageF& tmp, ImageF& out);
void half_resolution(const ImageF& img, ImageF& out);
void blur_and_halve(const ImageF& img, double sigma, ImageF& tmp, ImageF& out);

// gaussian_blur over part of the image only: the pixels of the blocks `need` marks (blocks of
// block x block pixels, ceil(w / block) per row, ceil(h / block) rows, row-major; nonzero = wanted)
// get gaussian_blur's values bit for bit (the same taps summed in the same order); the rest of
// `out` is unspecified. For a caller that knows most of an image needs no blur (flat parts: see
// line_segments.cpp). `out` is resized like gaussian_blur's; sigma <= 0 copies the image.
// Throws std::invalid_argument when block < 1 or need has the wrong size.
void gaussian_blur_blocks(const ImageF& img, double sigma, int block, std::span<const std::uint8_t> need, ImageF& tmp,
                          ImageF& out);

}  // namespace tagbench
