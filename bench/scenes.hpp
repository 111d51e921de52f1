#pragma once
// Synthetic test scenes for speed benchmarks and detector comparisons: a cluttered background with
// several tags of one family seen in perspective, fully determined by the seed.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/homography.hpp"

namespace tagbench::bench {

struct SceneTag {
  int id = 0;
  Corners corners;  // the black square's corners in the image, printed order TL, TR, BR, BL
};

struct Scene {
  cv::Mat image;  // 8-bit gray
  std::vector<SceneTag> tags;
};

// `count` tags of `family` (ids chosen by the seed), each 8-25 % of the image height across, tilted
// up to ~50 degrees, not overlapping, on a background of blurred random rectangles, a lighting
// gradient and mild noise. Rendered at 2x and area-averaged down, so edges are anti-aliased.
Scene make_scene(int width, int height, const std::string& family, int count, std::uint32_t seed);

}  // namespace tagbench::bench
