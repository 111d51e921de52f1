#pragma once
// The detector's image type: a plain grayscale float image, the input of every detect/ stage.
//
// Conventions shared by all of detect/:
//   - intensities are float in [0, 1] (0 = black, 1 = white);
//   - x points right, y points down; storage is row-major, data[y * width + x];
//   - pixel centres are at integer coordinates (OpenCV's convention): pixel (x, y) covers
//     [x - 0.5, x + 0.5] x [y - 0.5, y + 0.5], so the image spans [-0.5, width - 0.5] in x.
// cv::Mat appears only in to_float_image(), the edge where images enter the detector.
#include <cstddef>
#include <vector>

namespace cv {
class Mat;
}

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

// Converts an 8-bit (/255), 16-bit (/65535) or 32-bit float (taken as already in [0, 1]) cv::Mat
// with 1 (gray), 3 (BGR) or 4 (BGRA) channels to a gray ImageF. Colour is reduced with OpenCV's
// BGR->gray weights (0.299 R + 0.587 G + 0.114 B) after scaling to float, so no 8-bit rounding.
// Throws std::invalid_argument for any other depth or channel count, and for an empty Mat.
ImageF to_float_image(const cv::Mat& gray_or_color);
// The same into a caller-owned image whose storage is reused (the detector's workspace); `scratch`
// holds the scaled colour image for 3- and 4-channel input and keeps its storage too.
void to_float_image(const cv::Mat& gray_or_color, ImageF& out, cv::Mat& scratch);

}  // namespace tagbench
