#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

#include "detect/blur.hpp"
#include "detect/threshold.hpp"
#include "synthetic.hpp"

namespace test_threshold {

using namespace tagbench;

TEST(Threshold, FlatImageIsUnknownEverywhere) {
  ImageF img(23, 17, 0.4f);
  const TernaryImage t = adaptive_threshold(img);
  ASSERT_EQ(t.width, 23);
  ASSERT_EQ(t.height, 17);
  for (auto v : t.data) EXPECT_EQ(v, kTernaryUnknown);
}

TEST(Threshold, StepEdgeIsClassedOnBothSidesAndFarRegionsAreUnknown) {
  // Dark left half, light right half; 41 wide so the last tile is partial.
  ImageF img(41, 10, 0.9f);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) img.at(x, y) = 0.1f;
  const TernaryImage t = adaptive_threshold(img);
  for (int y = 0; y < 10; ++y) {
    EXPECT_EQ(t.at(19, y), kTernaryDark);
    EXPECT_EQ(t.at(20, y), kTernaryLight);
    EXPECT_EQ(t.at(0, y), kTernaryUnknown);   // tiles 0-1 and their neighbours see only dark
    EXPECT_EQ(t.at(40, y), kTernaryUnknown);  // the partial last tile and its neighbours see only light
  }
}

TEST(Threshold, ContrastBelowTheMinimumIsUnknownAboveIsClassed) {
  ImageF img(16, 16, 0.5f);
  for (int y = 0; y < 16; ++y)
    for (int x = 8; x < 16; ++x) img.at(x, y) = 0.5f + 3.0f / 255.0f;
  ThresholdOptions opt;
  EXPECT_EQ(adaptive_threshold(img, opt).at(8, 3), kTernaryUnknown);
  opt.min_contrast = 2.0f / 255.0f;
  const TernaryImage t = adaptive_threshold(img, opt);
  EXPECT_EQ(t.at(7, 3), kTernaryDark);
  EXPECT_EQ(t.at(8, 3), kTernaryLight);
}

TEST(Threshold, FollowsALightingGradient) {
  // A square whose dark is brighter than the far side's light: a global threshold cannot split both.
  ImageF img(64, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const float light = 0.2f + 0.7f * x / 63.0f;
      img.at(x, y) = ((x / 8) % 2 == 0) ? light : 0.45f * light;
    }
  ThresholdOptions opt;
  opt.tile_size = 4;  // 3 x 3 tiles of 4 px span a dark and a light 8 px stripe everywhere
  opt.min_contrast = 5.0f / 255.0f;
  const TernaryImage t = adaptive_threshold(img, opt);
  // Every pixel whose 3 x 3-tile window spans a dark and a light stripe (all but the outermost tiles).
  for (int x = 4; x < 60; ++x) EXPECT_EQ(t.at(x, 16), (x / 8) % 2 == 0 ? kTernaryLight : kTernaryDark) << x;
}

TEST(Threshold, RefusesBadOptions) {
  ImageF img(8, 8, 0.5f);
  ThresholdOptions opt;
  opt.tile_size = 0;
  EXPECT_THROW(adaptive_threshold(img, opt), std::invalid_argument);
  opt = {};
  opt.min_contrast = -1;
  EXPECT_THROW(adaptive_threshold(img, opt), std::invalid_argument);
}

TEST(Threshold, ScratchReuseGivesTheSameResultWithoutReallocating) {
  ImageF img = synth::render_convex_polygon(40, 30, {{10, 8}, {30, 9}, {29, 22}, {11, 21}}, 0.1f, 0.9f, 4);
  ThresholdScratch s;
  TernaryImage a, b;
  adaptive_threshold(img, {}, s, a);
  const auto* p = a.data.data();
  const auto* q = s.tile_min.data();
  adaptive_threshold(img, {}, s, a);
  EXPECT_EQ(a.data.data(), p);
  EXPECT_EQ(s.tile_min.data(), q);
  adaptive_threshold(img, {}, s, b);
  EXPECT_EQ(a.data, b.data);
}

namespace {
// The definition of a pixel's window: min and max over the pixels of the 3 x 3 tiles (tile size t)
// around the pixel's tile.
std::pair<float, float> window_min_max(const tagbench::ImageF& img, int t, int x, int y) {
  const int w = img.width, h = img.height, tw = (w + t - 1) / t, th = (h + t - 1) / t;
  float mn = 2, mx = -1;
  for (int ty = std::max(0, y / t - 1); ty <= std::min(th - 1, y / t + 1); ++ty)
    for (int tx = std::max(0, x / t - 1); tx <= std::min(tw - 1, x / t + 1); ++tx)
      for (int yy = ty * t; yy < std::min(h, ty * t + t); ++yy)
        for (int xx = tx * t; xx < std::min(w, tx * t + t); ++xx) {
          mn = std::min(mn, img.at(xx, yy));
          mx = std::max(mx, img.at(xx, yy));
        }
  return {mn, mx};
}
}  // namespace

// The tile pipeline (tile min / max, 3 x 3 tile widening, per-column midpoints) against the
// definition, pixel by pixel: min and max over the pixels of the 3 x 3 tiles around the pixel's
// tile, flat below min_contrast, light above the midpoint. Odd sizes, partial tiles, every tile size
// the stage specialises and others, one-tile-wide and one-row images.
TEST(Threshold, EqualsThePerPixelDefinitionOnRandomImages) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {2, 3}, {37, 23}, {64, 48}, {101, 7}};
  for (const auto& wh : sizes)
    for (const int t : {1, 2, 3, 4, 5, 8}) {
      const int w = wh[0], h = wh[1];
      ImageF img(w, h);
      // Blocks of random grey plus noise, so some tiles are flat and some are not.
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = ((x / 5 + y / 3) % 3 == 0) ? 0.5f + 0.01f * u(rng) : u(rng);
      ThresholdOptions opt;
      opt.tile_size = t;
      const TernaryImage got = adaptive_threshold(img, opt);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const auto [mn, mx] = window_min_max(img, t, x, y);
          const std::uint8_t want = mx - mn < opt.min_contrast ? kTernaryUnknown
                                    : img.at(x, y) > mn + 0.5f * (mx - mn) ? kTernaryLight
                                                                           : kTernaryDark;
          ASSERT_EQ(got.at(x, y), want) << w << "x" << h << " tile " << t << " at " << x << "," << y;
        }
    }
}

// The relative floor: a 12/255 step is flat under the absolute floor of 20/255 alone; with
// low_contrast 10/255 and weber_ratio 0.15 it is classed on a dark ground (12/255 of a 60/255 maximum,
// 0.2) and stays flat on a bright one (12/255 of 220/255, 0.05); a step under low_contrast stays flat.
TEST(Threshold, RelativeFloorClassesLowContrastStepsOnDarkGroundOnly) {
  auto step_image = [](float lo, float step) {
    ImageF img(16, 16, lo);
    for (int y = 0; y < 16; ++y)
      for (int x = 8; x < 16; ++x) img.at(x, y) = lo + step;
    return img;
  };
  ThresholdOptions opt;
  const ImageF dark = step_image(48.0f / 255, 12.0f / 255), bright = step_image(208.0f / 255, 12.0f / 255);
  EXPECT_EQ(adaptive_threshold(dark, opt).at(8, 3), kTernaryUnknown);
  opt.low_contrast = 10.0f / 255;
  opt.weber_ratio = 0.15f;
  const TernaryImage d = adaptive_threshold(dark, opt);
  EXPECT_EQ(d.at(7, 3), kTernaryDark);
  EXPECT_EQ(d.at(8, 3), kTernaryLight);
  EXPECT_EQ(adaptive_threshold(bright, opt).at(8, 3), kTernaryUnknown);
  EXPECT_EQ(adaptive_threshold(step_image(20.0f / 255, 8.0f / 255), opt).at(8, 3), kTernaryUnknown);  // 8 < 10
  // Steps at or above min_contrast are classed whatever the ratio.
  opt.weber_ratio = 1.0f;
  EXPECT_EQ(adaptive_threshold(step_image(200.0f / 255, 25.0f / 255), opt).at(8, 3), kTernaryLight);
  // Bad values are refused.
  opt.weber_ratio = -0.1f;
  EXPECT_THROW(adaptive_threshold(dark, opt), std::invalid_argument);
  opt = {};
  opt.low_contrast = std::nanf("");
  EXPECT_THROW(adaptive_threshold(dark, opt), std::invalid_argument);
}

// The relative floor against its definition, pixel by pixel, as the test above for min_contrast.
TEST(Threshold, RelativeFloorEqualsItsDefinitionOnRandomImages) {
  std::mt19937 rng(18);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const int w = 53, h = 37;
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = (x / 12 % 2 ? 0.15f : 0.75f) + 0.08f * u(rng);
  for (const int t : {2, 3}) {
    ThresholdOptions opt;
    opt.tile_size = t;
    opt.low_contrast = 10.0f / 255;
    opt.weber_ratio = 0.2f;
    const TernaryImage got = adaptive_threshold(img, opt);
    int relative = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto [mn, mx] = window_min_max(img, t, x, y);
        const float d = mx - mn;
        const bool flat = d < opt.min_contrast && (d < opt.low_contrast || d < opt.weber_ratio * mx);
        relative += d < opt.min_contrast && !flat;
        const std::uint8_t want = flat ? kTernaryUnknown : img.at(x, y) > mn + 0.5f * d ? kTernaryLight : kTernaryDark;
        ASSERT_EQ(got.at(x, y), want) << "tile " << t << " at " << x << "," << y;
      }
    EXPECT_GT(relative, 0) << "tile " << t;  // the relative floor decided some pixels
  }
}

// The local-mean rule (ThresholdOptions::mean_sigma): a 3 px light ring between a dark border and a
// dark card, bright ground 2 px beyond the card. Against the window's midpoint the ring is dark (the
// ground sets the maximum); against the local mean it is light. Flatness is still the tiles'.
TEST(Threshold, LocalMeanRuleKeepsAThinRingLightNextToBrighterGround) {
  const int w = 40, h = 12;
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(x, y) = x < 10 ? 0.15f : x < 13 ? 0.45f : x < 15 ? 0.25f : 0.95f;  // border, ring 10-12, card, ground
  ThresholdOptions opt;
  const TernaryImage mid = adaptive_threshold(img, opt);
  opt.mean_sigma = 1.5f;
  const TernaryImage mean = adaptive_threshold(img, opt);
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(mid.at(12, y), kTernaryDark);    // the ring's outer pixel (its window x 10-15 sees the ground)
    EXPECT_EQ(mean.at(12, y), kTernaryLight);  // under the mean rule light
    EXPECT_EQ(mean.at(8, y), kTernaryDark);    // the border stays dark
    EXPECT_EQ(mean.at(14, y), kTernaryDark);   // the card beside the ground too
    EXPECT_EQ(mean.at(0, y), kTernaryUnknown); // flat far from any step: unknown under both rules
    EXPECT_EQ(mean.at(39, y), kTernaryUnknown);
  }
  // Against its definition: the image blurred by mean_sigma (blur.hpp), pixel by pixel.
  const ImageF m = gaussian_blur(img, opt.mean_sigma);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (mid.at(x, y) == kTernaryUnknown) continue;
      ASSERT_EQ(mean.at(x, y), img.at(x, y) > m.at(x, y) ? kTernaryLight : kTernaryDark) << x << "," << y;
    }
  opt.mean_sigma = -1;
  EXPECT_THROW(adaptive_threshold(img, opt), std::invalid_argument);
  opt.mean_sigma = std::nanf("");
  EXPECT_THROW(adaptive_threshold(img, opt), std::invalid_argument);
}

}  // namespace test_threshold
