#pragma once
// The detector's image type: a plain grayscale float image, the input of every detect/ stage.
//
// Conventions shared by all of detect/:
//   - intensities are float in [0, 1] (0 = black, 1 = white);
//   - x points right, y points down; storage is row-major, data[y * width + x];
//   - pixel centres are at integer coordinates (OpenCV's convention): pixel (x, y) covers
//     [x - 0.5, x + 0.5] x [y - 0.5, y + 0.5], so the image spans [-0.5, width - 0.5] in x.
// No OpenCV here: cv::Mat input goes through detect/detector_opencv.hpp, the one header of the
// library that names OpenCV; a plain 8-bit buffer enters through ImageU8View below.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tagbench {

struct ImageF {
  int width = 0;
  int height = 0;
  std::vector<float> data;  // row-major, width * height values

  ImageF() = default;
  ImageF(int w, int h, float fill = 0.0f)
      : width(w), height(h), data(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

  bool empty() const { return width <= 0 || height <= 0; }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
  }
  float at(int x, int y) const { return data[index(x, y)]; }
  float& at(int x, int y) { return data[index(x, y)]; }
  // Border handling by clamping: coordinates outside the image read the nearest edge pixel.
  float at_clamped(int x, int y) const {
    x = x < 0 ? 0 : (x >= width ? width - 1 : x);
    y = y < 0 ? 0 : (y >= height ? height - 1 : y);
    return at(x, y);
  }
};

// A caller-owned 8-bit gray image, not copied: pixel (x, y) is data[y * stride + x] (stride in
// bytes, >= width), 0 = black, 255 = white. The entry point for callers without OpenCV.
struct ImageU8View {
  int width = 0;
  int height = 0;
  int stride = 0;
  const std::uint8_t* data = nullptr;
};

// Converts an 8-bit gray view to float (value / 255, the same floats as the cv::Mat conversion of
// an 8-bit gray Mat, detector_opencv.hpp). Throws std::invalid_argument for an empty view (width or
// height < 1, or no data) or a stride below the width.
ImageF to_float_image(const ImageU8View& gray);
// The same into a caller-owned image whose storage is reused (the detector's workspace).
void to_float_image(const ImageU8View& gray, ImageF& out);

// A gamma-encoded intensity made linear: v^gamma (value = linear^(1 / gamma), DetectorOptions::
// input_gamma), negative values taken as 0; gamma 1 returns v as it is.
inline float linearised(float v, double gamma) {
  return gamma == 1.0 ? v : static_cast<float>(std::pow(std::max(0.0f, v), gamma));
}

}  // namespace tagbench
