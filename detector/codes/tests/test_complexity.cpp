#include <gtest/gtest.h>

#include <random>

#include "codes/bits.hpp"
#include "codes/complexity.hpp"

namespace test_complexity {

using namespace tagbench;

TEST(Complexity, UniformPatternsNeedOneRectangle) {
  for (int d = 3; d <= 8; ++d) {
    EXPECT_EQ(rectangle_complexity(0, d), 1);
    EXPECT_EQ(rectangle_complexity(low_mask(d * d), d), 1);
  }
}

TEST(Complexity, HandMadeCases) {
  // One white cell in a black field: a black square, then the white cell.
  EXPECT_EQ(rectangle_complexity(Code{1} << 14, 6), 2);
  // Top half white, bottom half black (painter's rows 0..2 are bits 0..17).
  EXPECT_EQ(rectangle_complexity(low_mask(18), 6), 2);
  // A black-white-black stripe (the paper's example): two rectangles.
  const Code middle_column = (Code{1} << 1) | (Code{1} << 4) | (Code{1} << 7);  // 3x3, column 1 white
  EXPECT_EQ(rectangle_complexity(middle_column, 3), 2);
  // 3x3 checkerboard, corners and centre white (5 cells): greedy paints white, then the 4 black cells.
  const Code checker = 0b101010101;
  EXPECT_EQ(rectangle_complexity(checker, 3), 5);
}

TEST(Complexity, EarlyExitAgreesWithFullCount) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const int d = 3 + static_cast<int>(rng() % 4);
    const Code w = rng() & low_mask(d * d);
    const int c = rectangle_complexity(w, d);
    for (int t = 0; t <= c + 1; ++t) EXPECT_EQ(complexity_at_least(w, d, t), c >= t) << std::hex << w;
  }
}

TEST(Complexity, NeverMoreThanOneRectanglePerCell) {
  std::mt19937_64 rng(4);
  for (int i = 0; i < 500; ++i) {
    const Code w = rng() & low_mask(36);
    const int c = rectangle_complexity(w, 6);
    EXPECT_GE(c, 1);
    EXPECT_LE(c, 36);
  }
}

}  // namespace test_complexity
