#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "detect/noise_estimate.hpp"
#include "detect/threshold_quads.hpp"

namespace test_noise_estimate {

using namespace tagbench;

namespace {

// A scene without noise: smooth shading, a few hard-edged rectangles (straight edges the estimator's
// mask cancels along their length); then, with sigma_grey > 0, Gaussian noise of that many grey
// levels, quantised to 8 bits as a camera's frame is.
ImageF scene(int w, int h, double sigma_grey, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = 0.3 + 0.4 * x / w + 0.1 * y / h;
      if ((x / 40 + y / 30) % 3 == 0) v *= 0.4;  // rectangles
      v = 255 * v + (sigma_grey > 0 ? sigma_grey * noise(rng) : 0.0);
      img.at(x, y) = static_cast<float>(std::clamp(std::round(v), 0.0, 255.0) / 255.0);
    }
  return img;
}

}  // namespace

TEST(NoiseEstimate, MeasuresGaussianNoiseInGreyLevels) {
  // 8-bit quantisation adds sqrt(1/12) = 0.29 grey level of its own, which matters only for faint noise.
  for (const double sigma : {1.0, 2.0, 4.0}) {
    const double est = estimate_noise_grey(scene(320, 240, sigma, 7), 1);
    EXPECT_NEAR(est, std::sqrt(sigma * sigma + 1.0 / 12), 0.1 * sigma) << sigma;
  }
}

TEST(NoiseEstimate, EdgesAndShadingAloneReadAsNearlyNoiseless) {
  EXPECT_LT(estimate_noise_grey(scene(320, 240, 0.0, 1), 1), 0.3);  // the quantisation alone
}

TEST(NoiseEstimate, SubsampledRowsAndColumnsGiveNearlyTheSameAndTinyImagesZero) {
  const ImageF img = scene(320, 240, 2.0, 3);
  EXPECT_NEAR(estimate_noise_grey(img, 2), estimate_noise_grey(img, 1), 0.1);
  EXPECT_NEAR(estimate_noise_grey(img, 7, 2), estimate_noise_grey(img, 1), 0.1);  // the threshold stage's
  EXPECT_EQ(estimate_noise_grey(ImageF(2, 10, 0.5f)), 0.0);
  EXPECT_EQ(estimate_noise_grey(ImageF()), 0.0);
}

// The threshold stage blurs a noisy image (noise_blur) and leaves a clean one alone; without the
// option it does not look; a fixed blur_sigma takes precedence; half resolution never looks.
TEST(NoiseEstimate, ThresholdStageBlursOnlyNoisyImages) {
  ThresholdQuadOptions opt;
  opt.noise_blur.enabled = true;
  ThresholdQuadWorkspace ws;
  std::vector<Quad> quads;
  ThresholdQuadStats st;
  find_threshold_quads(scene(320, 240, 3.0, 5), opt, ws, quads, &st);
  EXPECT_GE(st.noise_grey, opt.noise_blur.min_noise_grey);
  EXPECT_EQ(st.blur_sigma, opt.noise_blur.sigma);
  find_threshold_quads(scene(320, 240, 0.0, 5), opt, ws, quads, &st);
  EXPECT_GE(st.noise_grey, 0.0);
  EXPECT_LT(st.noise_grey, opt.noise_blur.min_noise_grey);
  EXPECT_EQ(st.blur_sigma, 0.0);
  opt.blur_sigma = 0.5;
  find_threshold_quads(scene(320, 240, 3.0, 5), opt, ws, quads, &st);
  EXPECT_EQ(st.noise_grey, -1.0);
  EXPECT_EQ(st.blur_sigma, 0.5);
  opt.blur_sigma = 0;
  opt.halve = true;
  find_threshold_quads(scene(320, 240, 3.0, 5), opt, ws, quads, &st);
  EXPECT_EQ(st.blur_sigma, 0.0);
  opt.halve = false;
  opt.noise_blur.enabled = false;
  find_threshold_quads(scene(320, 240, 3.0, 5), opt, ws, quads, &st);
  EXPECT_EQ(st.noise_grey, -1.0);
  EXPECT_EQ(st.blur_sigma, 0.0);
}

}  // namespace test_noise_estimate
