#include "detect/image.hpp"

#include <stdexcept>
#include <string>

namespace tagbench {

ImageF to_float_image(const ImageU8View& gray) {
  ImageF out;
  to_float_image(gray, out);
  return out;
}

void to_float_image(const ImageU8View& gray, ImageF& out) {
  if (gray.width < 1 || gray.height < 1 || gray.data == nullptr)
    throw std::invalid_argument("to_float_image: empty image");
  if (gray.stride < gray.width)
    throw std::invalid_argument("to_float_image: stride " + std::to_string(gray.stride) + " is below the width " +
                                std::to_string(gray.width));
  out.width = gray.width;
  out.height = gray.height;
  out.data.resize(static_cast<std::size_t>(gray.width) * static_cast<std::size_t>(gray.height));
  // The float nearest 1/255 times the value, rounded once: what OpenCV's convertTo(CV_32F, 1/255.)
  // computes (it narrows the scale to float), so both entry points give the detector the same floats.
  const float scale = static_cast<float>(1.0 / 255.0);
  float* dst = out.data.data();
  for (int y = 0; y < gray.height; ++y) {
    const std::uint8_t* row = gray.data + static_cast<std::size_t>(y) * static_cast<std::size_t>(gray.stride);
    for (int x = 0; x < gray.width; ++x) *dst++ = static_cast<float>(row[x]) * scale;
  }
}

}  // namespace tagbench
