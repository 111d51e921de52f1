#pragma once
// Per-pixel image gradients (paper section III-A, Fig. 3; minMag: docs/paper-to-code.md section 1).
//
// Conventions (see image.hpp): intensities in [0, 1], x right, y down, pixel centres at integers.
// Central differences WITHOUT the 1/2 factor, as Java computes them (docs/paper-to-code.md section 1):
//   Ix = I(x+1, y) - I(x-1, y),   Iy = I(x, y+1) - I(x, y-1),
//   mag   = Ix^2 + Iy^2           (the SQUARED magnitude; segmentation's min_mag 0.004 is on this),
//   theta = atan2(Iy, Ix)         in (-pi, pi]; the gradient points from dark towards light, and
//                                 since y points down, theta = +pi/2 means "brighter below".
// The 1-pixel image border has no central difference: mag = theta = 0 there.
#include <vector>

#include "image.hpp"

namespace tagbench {

struct Gradients {
  int width = 0;
  int height = 0;
  std::vector<float> mag;    // squared magnitude, row-major like ImageF
  std::vector<float> theta;  // direction in (-pi, pi], row-major
};

// theta_min_mag: theta is computed only where mag > theta_min_mag and is 0 elsewhere. The default
// (0) computes it everywhere that has a gradient; passing the segmentation's min_mag skips the
// atan2 on flat pixels, which the segmentation never looks at.
Gradients compute_gradients(const ImageF& img, float theta_min_mag = 0.0f);
// The same into a caller-owned Gradients whose vectors keep their storage (the detector's workspace).
void compute_gradients(const ImageF& img, float theta_min_mag, Gradients& out);

}  // namespace tagbench
