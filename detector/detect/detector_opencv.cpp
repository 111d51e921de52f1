#include "detect/detector_opencv.hpp"

#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/workspace_impl.hpp"

namespace tagbench {

ImageF to_float_image(const cv::Mat& src) {
  ImageF out;
  cv::Mat scratch;
  to_float_image(src, out, scratch);
  return out;
}

void to_float_image(const cv::Mat& src, ImageF& out, cv::Mat& scratch) {
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

  out.width = src.cols;
  out.height = src.rows;
  out.data.resize(static_cast<std::size_t>(src.cols) * static_cast<std::size_t>(src.rows));
  // A Mat header over out's storage: OpenCV's create() keeps a destination of the right size and
  // type, so the result is written straight into `out` (no extra full-size copy).
  cv::Mat dst(src.rows, src.cols, CV_32F, out.data.data());
  // Scale first, convert colour second, so colour images are not rounded to 8 bits on the way.
  if (channels == 1) {
    src.convertTo(dst, CV_32F, scale);
  } else {
    src.convertTo(scratch, CV_MAKETYPE(CV_32F, channels), scale);
    cv::cvtColor(scratch, dst, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  }
  // Would OpenCV ever reallocate instead, the pixels would be lost silently; refuse loudly.
  if (dst.data != reinterpret_cast<uchar*>(out.data.data()))
    throw std::logic_error("to_float_image: OpenCV did not write into the destination buffer");
}

std::vector<Detection> detect(const Detector& detector, const cv::Mat& image, DetectorTrace* trace,
                              StageTimings* timings) {
  DetectorWorkspace ws;
  return detect(detector, image, ws, trace, timings);
}

std::vector<Detection> detect(const Detector& detector, const cv::Mat& image, DetectorWorkspace& ws,
                              DetectorTrace* trace, StageTimings* timings) {
  if (image.empty() || image.cols < 1 || image.rows < 1) throw std::invalid_argument("empty image");
  detector.check_size(image.cols, image.rows);  // before the conversion allocates anything
  DetectorWorkspace::Impl& w = ws.impl();
  to_float_image(image, w.gray, w.colour);
  return detector.detect(w.gray, ws, trace, timings);
}

}  // namespace tagbench
