#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "detect/angle_order.hpp"

namespace test_angle_order {

using namespace tagbench;

// The pseudo-angle orders directions as atan2 does, over the whole turn starting at +x.
TEST(AngleOrder, PseudoAngleIsMonotoneInTheAngle) {
  float last = -1;
  for (int i = 0; i < 3600; ++i) {
    const double a = 2 * M_PI * i / 3600.0;
    const float k = pseudo_angle(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
    EXPECT_GT(k, last) << "step " << i;
    EXPECT_GE(k, 0.0f);
    EXPECT_LT(k, 4.0f);
    last = k;
  }
  EXPECT_FALSE(std::signbit(pseudo_angle(1, -0.0f)));  // -0 would order after every other key
  EXPECT_EQ(pseudo_angle(0, 0), 0.0f);
}

// The packed keys come out in std::sort's order: by angle, equal angles by index; every size from 0,
// angles spread or bunched, with many equal ones.
TEST(AngleOrder, SortsAsStdSortDoes) {
  std::mt19937 rng(7);
  AngleSortScratch scratch;
  for (int n = 0; n < 300; ++n)
    for (const int levels : {4, 1000, 1 << 20}) {
      std::uniform_int_distribution<int> level(0, levels - 1);
      std::uniform_real_distribution<float> bunch(0, 1);
      const float lo = bunch(rng) * 3.5f, span = n % 3 == 0 ? 0.01f : 4.0f - lo;
      std::vector<std::uint64_t> keys;
      for (int i = 0; i < n; ++i) {
        const float a = std::min(3.9999998f, lo + span * static_cast<float>(level(rng)) / static_cast<float>(levels));
        keys.push_back(angle_key(a, static_cast<std::uint32_t>(i)));
      }
      std::shuffle(keys.begin(), keys.end(), rng);
      auto expected = keys;
      std::sort(expected.begin(), expected.end());
      sort_angle_keys(keys, scratch);
      ASSERT_EQ(keys, expected) << "n " << n << " levels " << levels;
      for (std::size_t i = 1; i < keys.size(); ++i) {
        const float a = std::bit_cast<float>(static_cast<std::uint32_t>(keys[i - 1] >> 32));
        const float b = std::bit_cast<float>(static_cast<std::uint32_t>(keys[i] >> 32));
        ASSERT_TRUE(a < b || (a == b && index_of(keys[i - 1]) < index_of(keys[i])));
      }
    }
}

}  // namespace test_angle_order
