#pragma once
// tagbench detect: what it reads. Which paths are images or videos, directories expanded into their
// images (sorted), the unit of work (Job) and its result (Outcome), one-line error text, and the
// guard that silences the decoders' own stderr chatter while the main thread decodes.
#include <cstddef>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "cli/detect_explain.hpp"
#include "detect/detector.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

std::string lower(std::string s);
bool is_video_path(const fs::path& p);
bool is_image_path(const fs::path& p);

// One unit of work: an image file, a decoded video frame, or an input already known to have failed.
struct Job {
  std::size_t index = 0;
  std::string label;      // as reported: the path, or "video#frameN"
  cv::Mat frame;          // the decoded image or video frame
  int frame_number = -1;  // >= 0 for video frames
  std::string out_name;   // base name of drawn/debug files
  std::string error;      // non-empty: this input failed before any work
};

struct Outcome {
  std::string label;
  int frame_number = -1;
  std::string error;  // empty = success
  int width = 0, height = 0;
  double detect_ms = 0;
  std::vector<Detection> detections;
  std::vector<PointExplanation> explained;  // --explain, in the options' order
};

// A source after expanding directories: an image, a video, or an error.
struct Source {
  fs::path path;
  std::string label;
  bool video = false;
  std::string error;
  std::string out_name;
};

// Expands directories into their image files (sorted); a missing or unreadable input becomes a
// Source with an error, reported in input order with the others.
std::vector<Source> expand_inputs(const std::vector<std::string>& inputs);

// Image and video libraries print their own warnings and errors on stderr (libpng: "PNG input buffer
// is incomplete", libjpeg: "Premature end of JPEG file", ffmpeg: ...). They would break the
// one-line-per-error rule and repeat what our error line says, so decoding runs with stderr pointed
// at /dev/null. Only the main thread decodes and only the main thread prints, so nothing of ours is
// ever lost; the worker threads (detection, drawing) print nothing.
class QuietStderr {
 public:
  QuietStderr();
  ~QuietStderr();
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace tagbench::cli::detect_cmd
