#pragma once
// The pictures of `tagbench detect`: --draw (the paper's Fig. 1) and --debug-dir (the stage pictures
// of Figs. 3 and 4). Pixel centres at integer coordinates; drawing is sub-pixel (1/16 px).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/detector.hpp"

namespace tagbench::cli {

// The input with every detection drawn: outline, a dot on the printed top-left corner, the id (with
// the family when several are loaded), and the pose axes (x red, y green, z blue into the tag).
cv::Mat draw_detections(const cv::Mat& image, const std::vector<Detection>& dets, const DetectorOptions& opt,
                        bool several_families);

// Names of the eight stage pictures, in the order stage_pictures returns them. The gradient
// finder (the paper profile) has the first four, the threshold finder (the default profile) the
// next two; quads and samples are every profile's. A stage a profile lacks is an empty Mat.
inline constexpr const char* kStages[] = {"gradient_magnitude", "gradient_direction", "clusters", "segments",
                                          "threshold",          "boundaries",         "quads",    "samples"};
std::vector<cv::Mat> stage_pictures(const ImageF& gray, const DetectorTrace& trace, const std::vector<Detection>& dets,
                                    const Detector& det);

// A picture encoded for a file extension (".png", ".jpg"); throws if OpenCV cannot encode it.
std::string encode(const cv::Mat& img, const std::string& ext);

}  // namespace tagbench::cli
