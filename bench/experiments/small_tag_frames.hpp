#pragma once
// Frames for the small-tag experiment (issue 17), each with its tags' ground truth:
//   realistic  bench/realistic (make_realistic_frame): small oblique tags on cluttered ground, defocus,
//              noise, JPEG; `count` frames of the set seeded `seed`
//   distance   the ray-traced distance sweep (raytrace/sweeps.hpp, Fig. 10's frames: face-on 1 m tag),
//              at the given distances (m), `count` trials each, rendered (cached) by POV-Ray
//   blur       the ray-traced conditions sweep's defocus condition, `count` trials per strength
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/homography.hpp"

namespace tagbench::bench::experiments {

struct TruthTag {
  int id = 0;
  Corners corners;           // printed TL, TR, BR, BL
  double black_square_px = 0;
  double tilt_deg = 0;
};

struct TruthFrame {
  std::string label;         // source and index, e.g. "realistic#12", "distance 25 m #3"
  double condition = 0;      // realistic: defocus sigma px; distance: metres; blur: strength
  cv::Mat gray8;
  std::vector<TruthTag> tags;
};

struct FrameSource {
  std::string kind = "realistic";   // realistic | distance | blur
  int count = 20;
  std::uint64_t seed = 1;
  std::vector<double> steps;        // distance: metres; blur: strengths (empty: the sweep's defaults)
  std::filesystem::path cache;      // render cache (distance, blur)
  int processes = 1;                // povray processes
};

// Throws std::invalid_argument for an unknown kind; std::runtime_error when rendering fails.
std::vector<TruthFrame> make_frames(const FrameSource& source);

}  // namespace tagbench::bench::experiments
