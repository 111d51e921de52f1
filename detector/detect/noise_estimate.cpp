#include "detect/noise_estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace tagbench {

double estimate_noise_grey(const ImageF& img, int rows_step, int cols_step) {
  if (img.width < 3 || img.height < 3) return 0;
  rows_step = std::max(1, rows_step);
  cols_step = std::max(1, cols_step);
  // Responses over kMaxGrey (edges, not noise) share the top bin: the median stays exact below it.
  constexpr int kBinsPerGrey = 4, kMaxGrey = 64;
  constexpr float kScale = 255.0f * kBinsPerGrey, kTop = kBinsPerGrey * kMaxGrey;
  std::array<std::uint32_t, kBinsPerGrey * kMaxGrey + 1> hist{};
  std::uint64_t count = 0;
  const int w = img.width;
  for (int y = 1; y + 1 < img.height; y += rows_step) {
    const float* a = img.data.data() + img.index(0, y - 1);
    const float* b = a + w;
    const float* c = b + w;
    for (int x = 1; x + 1 < w; x += cols_step) {
      const float r = (a[x - 1] + a[x + 1] + c[x - 1] + c[x + 1]) - 2 * (a[x] + c[x] + b[x - 1] + b[x + 1]) + 4 * b[x];
      // Through int: a float's conversion to an unsigned type is several instructions on x86-64.
      ++hist[static_cast<std::size_t>(static_cast<int>(std::min(std::abs(r) * kScale, kTop) + 0.5f))];
      ++count;
    }
  }
  // The median bin: the first whose cumulative count reaches half.
  std::uint64_t seen = 0;
  std::size_t k = 0;
  for (; k < hist.size(); ++k) {
    seen += hist[k];
    if (2 * seen >= count) break;
  }
  // |response| of Gaussian noise is half-normal with sigma 6 sigma_noise (the mask's squares sum to
  // 36), whose median is 0.6745 of it.
  return static_cast<double>(k) / kBinsPerGrey / (6 * 0.6744897501960817);
}

}  // namespace tagbench
