#pragma once
// The realistic set's tests' camera: it only quantizes (no blur, noise or JPEG loss to speak of), for
// isolating one degradation or reading tags as rendered. 320 x 240, f = 320 px, 2-3 tags a frame.
#include "realistic/realistic_set.hpp"

namespace tagbench::bench::testing {

inline RealisticSettings clean_camera() {
  RealisticSettings s;
  s.width = 320;
  s.height = 240;
  s.focal_px = 320;
  s.min_tags = 2;
  s.max_tags = 3;
  s.blur_sigma_px = {0, 0};
  s.motion_blur_px = {0, 0};
  s.full_well_e = {1e7, 1e7};
  s.read_noise_e = {0, 0};
  s.jpeg_quality = {100, 100};
  return s;
}

}  // namespace tagbench::bench::testing
