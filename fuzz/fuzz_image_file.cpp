// Fuzz target: image files through the loader of `tagbench detect` (cli/image_file.hpp), the whole
// input being the file's bytes, then (for images small enough to keep runs fast) through the
// detector exactly as the command runs it.
//
// What must hold: decode_image() returns a non-empty image or throws std::runtime_error (one line);
// the detector on what it returns either detects or refuses an unsupported pixel type with
// std::invalid_argument (the command's error line for that input).
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "cli/image_file.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "fuzz_util.hpp"

namespace {
constexpr long kMaxDetectPixels = 1 << 14;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const tagbench::Detector* detector = [] {
    cv::setNumThreads(1);
    // As in `tagbench detect`: decoder warnings are not errors of ours.
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    tagbench::DetectorOptions opt;
    opt.families = {"36h11", "16h5"};
    return new tagbench::Detector(opt);  // lives as long as the process
  }();

  const std::string bytes(reinterpret_cast<const char*>(data), size);
  cv::Mat img;
  try {
    img = tagbench::cli::decode_image(bytes);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    FUZZ_CHECK(!what.empty() && what.find('\n') == std::string::npos, "not a one-line error: " + what);
    return 0;
  }
  FUZZ_CHECK(!img.empty() && img.cols > 0 && img.rows > 0, "decode_image returned an empty image");
  if (static_cast<long>(img.total()) > kMaxDetectPixels) return 0;
  try {
    (void)detect(*detector, img);
  } catch (const std::invalid_argument& e) {
    const int depth = img.depth(), ch = img.channels();
    const bool supported = (depth == CV_8U || depth == CV_16U || depth == CV_32F) && (ch == 1 || ch == 3 || ch == 4);
    FUZZ_CHECK(!supported, std::string("the detector refused a decoded image: ") + e.what());
  }
  return 0;
}
