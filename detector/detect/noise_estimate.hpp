#pragma once
// Beyond the paper and AprilTag 3: an image's noise level, to choose the threshold stage's blur per
// image (ThresholdQuadOptions::noise_blur). Immerkaer's estimator (J. Immerkaer, "Fast noise variance
// estimation", CVIU 64(2), 1996): the image filtered with the 3 x 3 mask
//    1 -2  1
//   -2  4 -2
//    1 -2  1
// (the difference of two Laplacians, which cancels smooth shading and straight edges), over the
// interior pixels. The median of the absolute response (robust to the edges and texture that remain)
// over 6 x 0.6745 estimates a Gaussian noise's sigma (Immerkaer averages the absolute response; the
// median keeps the edges out). Camera sharpening (an unsharp mask before
// JPEG) multiplies the fine-scale noise, and shows here as a high sigma.
//
// Units: intensities as image.hpp ([0, 1]); the result in grey levels (x 255), so that 8-bit images
// give the same number as the literature's. The median is taken over a quarter-grey-level histogram
// of the responses (those over 64 grey levels in its top bin), so the result moves in steps of
// 0.06 grey level and stops at about 16 (a median response of 64).
#include "image.hpp"

namespace tagbench {

// Noise sigma of `img` in grey levels (0 for images under 3 x 3). `rows_step`, `cols_step` >= 1:
// only every rows_step-th interior row and cols_step-th column is filtered (a cheaper estimate of the
// same quantity). The threshold stage takes every 2nd column and 32 or more rows, every 16th at most
// (a 640 x 480 image: every 14th row, some 10,000 responses): every 2nd row took 0.2 ms of a 400 x
// 400 ray-traced frame, a fifth of the whole detector's time there; this about 0.015 ms alone, 3-4 %
// of the detector's time on those frames (measured end to end against the option off).
double estimate_noise_grey(const ImageF& img, int rows_step = 1, int cols_step = 1);

}  // namespace tagbench
