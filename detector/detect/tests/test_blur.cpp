#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "detect/blur.hpp"

namespace test_blur {

using namespace tagbench;

namespace {

ImageF random_image(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  ImageF img(w, h);
  for (float& v : img.data) v = u(rng);
  return img;
}

// Row of a vertical step edge at x = edge, dark (0) on the left, light (1) on the right, with exact
// area antialiasing: pixel i covers [i - 0.5, i + 0.5].
ImageF step_edge(int w, int h, double edge) {
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = static_cast<float>(std::clamp(x + 0.5 - edge, 0.0, 1.0));
  return img;
}

// Location of such an edge recovered from the light area of row y: sum_x I = (w - 0.5) - edge.
// Any mapping error between resolutions shows up directly in this number.
double edge_from_area(const ImageF& img, int y) {
  double s = 0.0;
  for (int x = 0; x < img.width; ++x) s += img.at(x, y);
  return img.width - 0.5 - s;
}

}  // namespace

TEST(Blur, KernelIsNormalisedSymmetricGaussianWithRadiusCeil3Sigma) {
  for (double sigma : {0.5, 0.8, 1.0, 1.3, 2.0}) {
    const int r = gaussian_radius(sigma);
    EXPECT_EQ(r, static_cast<int>(std::ceil(3 * sigma)));
    const std::vector<float> k = gaussian_kernel(sigma);
    ASSERT_EQ(k.size(), static_cast<std::size_t>(2 * r + 1));
    EXPECT_NEAR(std::accumulate(k.begin(), k.end(), 0.0), 1.0, 1e-6);
    for (int i = 0; i <= r; ++i) {
      EXPECT_EQ(k[r + i], k[r - i]);
      // Gaussian profile relative to the centre tap.
      EXPECT_NEAR(k[r + i] / k[r], std::exp(-0.5 * i * i / (sigma * sigma)), 1e-6) << sigma << " " << i;
    }
  }
  EXPECT_EQ(gaussian_kernel(0.0), std::vector<float>{1.0f});
}

TEST(Blur, SigmaZeroIsTheIdentity) {
  const ImageF img = random_image(13, 7, 1);
  EXPECT_EQ(gaussian_blur(img, 0.0).data, img.data);
  EXPECT_EQ(gaussian_blur(img, -1.0).data, img.data);
}

TEST(Blur, ConstantImageStaysConstantIncludingBorders) {
  ImageF img(9, 6, 0.37f);
  const ImageF b = gaussian_blur(img, kSegSigma);
  ASSERT_EQ(b.width, 9);
  ASSERT_EQ(b.height, 6);
  for (float v : b.data) EXPECT_NEAR(v, 0.37f, 1e-6);
}

TEST(Blur, ImpulseResponseIsTheSeparableGaussian) {
  const int n = 21, c = 10;
  ImageF img(n, n, 0.0f);
  img.at(c, c) = 1.0f;
  for (double sigma : {0.8, 1.5}) {
    const ImageF b = gaussian_blur(img, sigma);
    const int r = gaussian_radius(sigma);
    double z = 0.0;  // normalisation of the truncated 1-D kernel
    for (int i = -r; i <= r; ++i) z += std::exp(-0.5 * i * i / (sigma * sigma));
    double total = 0.0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int dx = x - c, dy = y - c;
        const double expected = (std::abs(dx) <= r && std::abs(dy) <= r)
                                    ? std::exp(-0.5 * (dx * dx + dy * dy) / (sigma * sigma)) / (z * z)
                                    : 0.0;
        EXPECT_NEAR(b.at(x, y), expected, 1e-6) << sigma << " " << dx << "," << dy;
        EXPECT_FLOAT_EQ(b.at(x, y), b.at(2 * c - x, y));  // mirror symmetric
        EXPECT_FLOAT_EQ(b.at(x, y), b.at(y, x));          // and the same along both axes
        total += b.at(x, y);
      }
    EXPECT_NEAR(total, 1.0, 1e-5);  // mass preserved away from the border
  }
}

// Clamping repeats the edge pixel outward: with a bright first column, x = 0 collects the centre
// tap and the whole left tail, g0 + (1 - g0) / 2, and x = 1 the whole left tail (1 - g0) / 2.
// (Zero padding would give g0 and the single tap g[-1].)
TEST(Blur, BordersAreClamped) {
  ImageF img(12, 5, 0.0f);
  for (int y = 0; y < 5; ++y) img.at(0, y) = 1.0f;
  const std::vector<float> k = gaussian_kernel(kSegSigma);
  const float g0 = k[k.size() / 2];
  const ImageF b = gaussian_blur(img, kSegSigma);
  for (int y = 0; y < 5; ++y) {
    EXPECT_NEAR(b.at(0, y), 0.5f + 0.5f * g0, 1e-6);
    EXPECT_NEAR(b.at(1, y), 0.5f * (1.0f - g0), 1e-6);
  }
}

TEST(Blur, HalfResolutionAveragesTwoByTwoBlocksAndDropsOddEdges) {
  ImageF img(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) img.at(x, y) = static_cast<float>(x + 10 * y);
  const ImageF h = half_resolution(img);
  ASSERT_EQ(h.width, 2);
  ASSERT_EQ(h.height, 1);
  EXPECT_FLOAT_EQ(h.at(0, 0), (0 + 1 + 10 + 11) / 4.0f);
  EXPECT_FLOAT_EQ(h.at(1, 0), (2 + 3 + 12 + 13) / 4.0f);
  EXPECT_TRUE(half_resolution(ImageF(1, 7)).empty());
}

TEST(Blur, FullFromHalfIsTwiceXPlusAHalf) {
  EXPECT_DOUBLE_EQ(full_from_half(0.0), 0.5);   // centre of full pixels 0 and 1
  EXPECT_DOUBLE_EQ(full_from_half(3.0), 6.5);   // centre of full pixels 6 and 7
  EXPECT_DOUBLE_EQ(full_from_half(-0.5), -0.5); // left image border maps onto itself
}

// A step edge measured at half resolution lands back on its true full-resolution position.
TEST(Blur, HalfResolutionEdgeMapsBackWithFullFromHalf) {
  for (double edge : {20.3, 21.0, 21.5, 22.77, 31.9}) {
    const ImageF full = step_edge(64, 4, edge);
    ASSERT_NEAR(edge_from_area(full, 0), edge, 1e-4);  // the measurement itself is exact
    const ImageF half = half_resolution(full);
    EXPECT_NEAR(full_from_half(edge_from_area(half, 1)), edge, 1e-4) << edge;
    // The same holds after the segmentation blur combined with the decimation.
    const ImageF bh = blur_and_halve(full, kSegSigma);
    EXPECT_NEAR(full_from_half(edge_from_area(bh, 1)), edge, 1e-4) << edge;
    // ...and the naive 2 x_half would be off by half a full-resolution pixel.
    EXPECT_GT(std::abs(2.0 * edge_from_area(half, 1) - edge), 0.49);
  }
}

TEST(Blur, BlurAndHalveEqualsBlurThenHalve) {
  for (auto [w, h] : {std::pair{37, 29}, std::pair{40, 6}, std::pair{3, 3}}) {
    const ImageF img = random_image(w, h, static_cast<unsigned>(w * h));
    for (double sigma : {0.8, 1.5, 3.0}) {
      const ImageF fused = blur_and_halve(img, sigma);
      const ImageF ref = half_resolution(gaussian_blur(img, sigma));
      ASSERT_EQ(fused.width, ref.width);
      ASSERT_EQ(fused.height, ref.height);
      for (std::size_t i = 0; i < ref.data.size(); ++i) EXPECT_NEAR(fused.data[i], ref.data[i], 2e-6) << w << "x" << h;
    }
    EXPECT_EQ(blur_and_halve(img, 0.0).data, half_resolution(img).data);
  }
}

// gaussian_blur's values are those of the plain separable sum, bit for bit: rows first, then columns,
// each output summing its taps in order from 0 in float, borders clamped. The vectorised passes
// (eight outputs at a time) must not change a value, at the tails or the borders either; the sizes
// give runs of 0-7 columns past the last full eight, images narrower than the kernel included.
TEST(Blur, GaussianBlurIsThePlainSeparableSumBitForBit) {
  const auto reference = [](const ImageF& img, double sigma) {
    const std::vector<float> k = gaussian_kernel(sigma);
    const int r = gaussian_radius(sigma), w = img.width, h = img.height;
    ImageF tmp(w, h), out(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float s = 0.0f;
        for (int t = 0; t <= 2 * r; ++t) s += k[static_cast<std::size_t>(t)] * img.at(std::clamp(x - r + t, 0, w - 1), y);
        tmp.at(x, y) = s;
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float s = 0.0f;
        for (int t = 0; t <= 2 * r; ++t) s += k[static_cast<std::size_t>(t)] * tmp.at(x, std::clamp(y - r + t, 0, h - 1));
        out.at(x, y) = s;
      }
    return out;
  };
  for (auto [w, h] : {std::pair{37, 29}, std::pair{64, 9}, std::pair{8, 8}, std::pair{3, 41}, std::pair{101, 17}}) {
    const ImageF img = random_image(w, h, static_cast<unsigned>(3 * w + h));
    for (double sigma : {0.5, 0.75, 1.04, 2.0, 6.0, 25.0}) {
      const ImageF got = gaussian_blur(img, sigma), want = reference(img, sigma);
      ASSERT_EQ(got.width, w);
      ASSERT_EQ(got.height, h);
      for (std::size_t i = 0; i < want.data.size(); ++i)
        ASSERT_EQ(got.data[i], want.data[i]) << w << "x" << h << " sigma " << sigma << " at " << i;
    }
  }
}

// The blur restricted to marked blocks gives gaussian_blur's values bit for bit on their pixels,
// borders, blocks cut by the image's edge and kernels wider than a block included.
TEST(Blur, BlocksGiveGaussianBlurBitForBitWhereMarked) {
  for (auto [w, h] : {std::pair{37, 29}, std::pair{64, 48}, std::pair{5, 70}}) {
    const ImageF img = random_image(w, h, static_cast<unsigned>(w + h));
    for (int block : {1, 4, 16}) {
      const int bw = (w + block - 1) / block, bh = (h + block - 1) / block;
      std::vector<std::uint8_t> need(static_cast<std::size_t>(bw * bh));
      std::mt19937 rng(static_cast<unsigned>(block));
      for (auto& n : need) n = rng() % 3 == 0;
      need.back() = 1;
      for (double sigma : {0.75, 2.0, 6.0}) {
        const ImageF ref = gaussian_blur(img, sigma);
        ImageF tmp, out(3, 3, 0.25f);  // a reused buffer of another size
        gaussian_blur_blocks(img, sigma, block, need, tmp, out);
        ASSERT_EQ(out.width, w);
        ASSERT_EQ(out.height, h);
        int compared = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            if (need[static_cast<std::size_t>(y / block * bw + x / block)]) {
              ASSERT_EQ(out.at(x, y), ref.at(x, y)) << w << "x" << h << " block " << block << " sigma " << sigma;
              ++compared;
            }
        EXPECT_GT(compared, 0);
      }
    }
  }
  ImageF tmp, out;
  const ImageF img = random_image(10, 10, 3);
  EXPECT_THROW(gaussian_blur_blocks(img, 1.0, 0, {}, tmp, out), std::invalid_argument);
  EXPECT_THROW(gaussian_blur_blocks(img, 1.0, 4, std::vector<std::uint8_t>(8, 1), tmp, out), std::invalid_argument);
  gaussian_blur_blocks(img, 0.0, 4, std::vector<std::uint8_t>(9, 0), tmp, out);
  EXPECT_EQ(out.data, img.data);
}

}  // namespace test_blur
