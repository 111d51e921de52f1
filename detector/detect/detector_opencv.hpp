#pragma once
// The detector's OpenCV edge: cv::Mat input. The only header of the library that needs OpenCV's
// headers; detector.hpp and everything it includes do not (a program that passes images as ImageF
// or ImageU8View builds without OpenCV on its include path). A target that includes this header
// links OpenCV (opencv_core) itself.
#include <vector>

#include <opencv2/core/mat.hpp>

#include "detector.hpp"
#include "image.hpp"

namespace tagbench {

// Converts an 8-bit (/255), 16-bit (/65535) or 32-bit float (taken as already in [0, 1]) cv::Mat
// with 1 (gray), 3 (BGR) or 4 (BGRA) channels to a gray ImageF. Colour is reduced with OpenCV's
// BGR->gray weights (0.299 R + 0.587 G + 0.114 B) after scaling to float, so no 8-bit rounding.
// Throws std::invalid_argument for any other depth or channel count, and for an empty Mat.
ImageF to_float_image(const cv::Mat& gray_or_color);
// The same into a caller-owned image whose storage is reused (the detector's workspace); `scratch`
// holds the scaled colour image for 3- and 4-channel input and keeps its storage too.
void to_float_image(const cv::Mat& gray_or_color, ImageF& out, cv::Mat& scratch);

// Detects tags in an 8-bit or 16-bit (or float in [0, 1]), gray or colour cv::Mat, converted as
// to_float_image does, into the workspace's buffers. Otherwise Detector::detect (detector.hpp):
// const, thread-safe with one workspace per thread; throws std::invalid_argument for an empty image
// and for one over options().max_pixels (checked before the conversion allocates anything).
std::vector<Detection> detect(const Detector& detector, const cv::Mat& image, DetectorWorkspace& workspace,
                              DetectorTrace* trace = nullptr, StageTimings* timings = nullptr);
// The same with a temporary workspace (allocates per call).
std::vector<Detection> detect(const Detector& detector, const cv::Mat& image, DetectorTrace* trace = nullptr,
                              StageTimings* timings = nullptr);

}  // namespace tagbench
