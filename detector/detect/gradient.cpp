#include "detect/gradient.hpp"

#include <cmath>
#include <numbers>

namespace tagbench {

Gradients compute_gradients(const ImageF& img, float theta_min_mag) {
  Gradients g;
  compute_gradients(img, theta_min_mag, g);
  return g;
}

void compute_gradients(const ImageF& img, float theta_min_mag, Gradients& g) {
  g.width = img.width;
  g.height = img.height;
  const std::size_t n = img.data.size();
  // assign() zeroes the border and the skipped thetas and keeps the capacity of a reused buffer.
  g.mag.assign(n, 0.0f);
  g.theta.assign(n, 0.0f);
  constexpr float kPi = std::numbers::pi_v<float>;
  for (int y = 1; y + 1 < img.height; ++y) {
    const float* up = &img.data[img.index(0, y - 1)];
    const float* mid = &img.data[img.index(0, y)];
    const float* down = &img.data[img.index(0, y + 1)];
    float* mag = &g.mag[img.index(0, y)];
    float* theta = &g.theta[img.index(0, y)];
    for (int x = 1; x + 1 < img.width; ++x) {
      const float ix = mid[x + 1] - mid[x - 1];
      const float iy = down[x] - up[x];
      const float m = ix * ix + iy * iy;
      mag[x] = m;
      if (m > theta_min_mag) {
        float t = std::atan2(iy, ix);
        // atan2 returns -pi for (-0, negative); fold it onto +pi so the range is (-pi, pi].
        theta[x] = t <= -kPi ? kPi : t;
      }
    }
  }
}

}  // namespace tagbench
