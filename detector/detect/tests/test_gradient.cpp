#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "detect/gradient.hpp"

namespace test_gradient {

using namespace tagbench;

namespace {
constexpr double kPi = std::numbers::pi;

ImageF ramp(int w, int h, double a, double b, double c) {
  ImageF img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = static_cast<float>(a * x + b * y + c);
  return img;
}
}  // namespace

// I = a x + b y + c: the undivided central differences are Ix = 2a, Iy = 2b everywhere inside.
TEST(Gradient, LinearRampGivesTwiceTheSlopeSquaredMagnitudeAndDirection) {
  const double a = 0.011, b = -0.004;
  const ImageF img = ramp(20, 15, a, b, 0.3);
  const Gradients g = compute_gradients(img);
  ASSERT_EQ(g.width, 20);
  ASSERT_EQ(g.height, 15);
  ASSERT_EQ(g.mag.size(), img.data.size());
  ASSERT_EQ(g.theta.size(), img.data.size());
  for (int y = 1; y < 14; ++y)
    for (int x = 1; x < 19; ++x) {
      EXPECT_NEAR(g.mag[img.index(x, y)], 4 * (a * a + b * b), 1e-7);
      EXPECT_NEAR(g.theta[img.index(x, y)], std::atan2(2 * b, 2 * a), 1e-4);
    }
}

TEST(Gradient, BorderIsZero) {
  const ImageF img = ramp(6, 5, 0.1, 0.05, 0.0);
  const Gradients g = compute_gradients(img);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x) {
      const bool border = x == 0 || y == 0 || x == 5 || y == 4;
      if (!border) continue;
      EXPECT_EQ(g.mag[img.index(x, y)], 0.0f) << x << "," << y;
      EXPECT_EQ(g.theta[img.index(x, y)], 0.0f) << x << "," << y;
    }
  EXPECT_GT(g.mag[img.index(2, 2)], 0.0f);
}

// The gradient points from dark to light; with y down, "brighter below" is +pi/2.
TEST(Gradient, DirectionPointsTowardsLightInImageCoordinates) {
  struct Case {
    double a, b, theta;
  };
  for (const Case& c : {Case{0.1, 0, 0}, Case{0, 0.1, kPi / 2}, Case{0, -0.1, -kPi / 2}, Case{-0.1, 0, kPi},
                        Case{0.1, 0.1, kPi / 4}, Case{-0.1, 0.1, 3 * kPi / 4}}) {
    const Gradients g = compute_gradients(ramp(5, 5, c.a, c.b, 0.5));
    EXPECT_NEAR(g.theta[2 * 5 + 2], c.theta, 1e-6) << c.a << " " << c.b;
  }
}

// atan2 gives -pi for a signed-zero y; the range is (-pi, pi], so brighter-to-the-left is +pi.
TEST(Gradient, ThetaRangeExcludesMinusPi) {
  // Brighter to the left with Iy = (-0) - (+0) = -0: atan2(-0, -1) is -pi, which must become +pi.
  ImageF img(5, 3, 0.0f);
  for (int x = 0; x < 5; ++x) img.at(x, 2) = -0.0f;
  img.at(0, 1) = 1.0f;
  const Gradients g = compute_gradients(img);
  EXPECT_FLOAT_EQ(g.theta[1 * 5 + 1], std::numbers::pi_v<float>);
}

TEST(Gradient, ThetaIsSkippedAtOrBelowTheThresholdButMagnitudeIsKept) {
  const ImageF img = ramp(5, 5, 0.01, 0.01, 0.0);  // mag = 4 * 2e-4 = 8e-4
  const Gradients all = compute_gradients(img);
  const Gradients some = compute_gradients(img, 0.001f);
  EXPECT_NEAR(all.theta[12], kPi / 4, 1e-6);
  EXPECT_EQ(some.theta[12], 0.0f);
  EXPECT_EQ(some.mag, all.mag);
}

}  // namespace test_gradient
