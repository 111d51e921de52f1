#pragma once
// The detection lines any detector can print (issue 12): one JSON object per image,
//   {"image": "FILE", "ms": 1.2 (optional), "detections": [{"family": "36h11", "id": 7,
//     "corners": [[x, y] x4], "pose": {"R": [[3] x3], "t": [x, y, z]} (optional),
//     "decision_margin": m (optional), "hamming": k (optional)}]}
// or {"image": "FILE", "error": "message"} when the detector failed on that image. Read by
// `tagbench score` and by the experiments' external detectors; written by `tagbench detect --format jsonl`.
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "raytrace/comparators.hpp"

namespace tagbench::bench {

struct ImageDetections {
  std::string image;         // as the line gives it
  std::size_t line = 0;      // 1-based, for messages
  std::vector<Found> found;  // as given (the detector's own convention)
  double ms = std::numeric_limits<double>::quiet_NaN();
  std::string error;         // the detector's own error for this image, when it gave one
};

// One line; throws std::runtime_error with what is wrong (no place: the caller names it).
ImageDetections parse_detection_line(std::string_view line);

// Every line (blank lines skipped). Throws std::runtime_error "SOURCE line N: what is wrong".
std::vector<ImageDetections> parse_detection_lines(const std::string& text, const std::string& source);

}  // namespace tagbench::bench
