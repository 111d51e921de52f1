#include "detect/image.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace tagbench {

ImageF to_float_image(const cv::Mat& src) {
  if (src.empty()) throw std::invalid_argument("to_float_image: empty image");
  double scale = 1.0;
  switch (src.depth()) {
    case CV_8U: scale = 1.0 / 255.0; break;
    case CV_16U: scale = 1.0 / 65535.0; break;
    case CV_32F: scale = 1.0; break;
    default: throw std::invalid_argument("to_float_image: unsupported depth " + std::to_string(src.depth()));
  }
  const int channels = src.channels();
  if (channels != 1 && channels != 3 && channels != 4)
    throw std::invalid_argument("to_float_image: unsupported channel count " + std::to_string(channels));

  // Scale first, convert colour second, so colour images are not rounded to 8 bits on the way.
  cv::Mat f;
  src.convertTo(f, CV_MAKETYPE(CV_32F, channels), scale);
  cv::Mat gray;
  if (channels == 3)
    cv::cvtColor(f, gray, cv::COLOR_BGR2GRAY);
  else if (channels == 4)
    cv::cvtColor(f, gray, cv::COLOR_BGRA2GRAY);
  else
    gray = f;

  ImageF out(gray.cols, gray.rows);
  const std::size_t row_bytes = static_cast<std::size_t>(gray.cols) * sizeof(float);
  for (int y = 0; y < gray.rows; ++y)  // row by row: the Mat need not be continuous
    std::memcpy(&out.data[out.index(0, y)], gray.ptr<float>(y), row_bytes);
  return out;
}

}  // namespace tagbench
