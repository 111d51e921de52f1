#pragma once
// The realistic set's internal stages (realistic_set.hpp): portable random draws, the cluttered
// ground, the light across the frame, and the camera. Not part of the API.
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "realistic/realistic_set.hpp"

namespace tagbench::bench::realistic_parts {

// splitmix64: portable, so a frame is the same on every standard library.
struct Draws {
  std::uint64_t state = 0;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double uniform(const Range& r) { return uniform(r.lo, r.hi); }
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }  // [0, n)
  bool chance(double p) { return uniform() < p; }
};

// The seed of frame `index` of a set seeded `seed`.
std::uint64_t frame_seed(std::uint64_t seed, int index);

// The ground's reflectance (CV_32F, 0..1) at supersampled size (width*ss x height*ss): multi-scale
// texture and clutter with straight edges, corners, outlines, text-like marks, paving grids and
// tag-like decoys. Sizes are drawn in output pixels, so the clutter looks the same at any ss.
cv::Mat make_ground(int width, int height, int ss, Draws& draws);

// The light falling on the scene at output size (CV_32F, about 0..1): a smooth variation of depth
// `unevenness` and, with probability `shadow_probability`, a hard-edged shadow (light x 0.35..0.6).
cv::Mat make_light(int width, int height, double unevenness, double shadow_probability, Draws& draws, bool& shadow);

// A uniform disk PSF of `radius` pixels (> 0), each pixel's weight its area inside the disk (8 x 8
// samples), summing to 1: a lens's defocus (RealisticSettings::disk_defocus).
cv::Mat disk_kernel(double radius);

// The camera: linear image (CV_32F, 1 = saturation) -> 8-bit gray. With settings.degrade: defocus,
// motion blur, shot and read noise, gamma, quantization, JPEG (jpeg receives the encoded bytes and
// the returned image is their decoding); without: quantization only. Records what it did in `d`.
cv::Mat apply_camera(const cv::Mat& linear, const RealisticSettings& settings, Draws& draws, CameraDegradation& d,
                     std::vector<std::uint8_t>& jpeg);

}  // namespace tagbench::bench::realistic_parts
