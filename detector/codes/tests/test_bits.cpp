#include <gtest/gtest.h>

#include <random>

#include "codes/bits.hpp"

namespace test_bits {

using namespace tagbench;

// rotate90 turns the printed payload clockwise: rotated(y, x) = original(d-1-x, y).
TEST(Bits, Rotate90IsClockwiseOnTheCellGrid) {
  for (int d = 3; d <= 8; ++d) {
    std::mt19937_64 rng(d);
    const Code w = rng() & low_mask(d * d);
    const Code r = rotate90(w, d);
    for (int y = 0; y < d; ++y)
      for (int x = 0; x < d; ++x)
        EXPECT_EQ((r >> cell_bit(d, y, x)) & 1, (w >> cell_bit(d, d - 1 - x, y)) & 1) << "d=" << d;
  }
}

TEST(Bits, TopLeftCellMovesToTopRight) {
  const int d = 6;
  const Code top_left = Code{1} << 35;  // MSB = top-left cell
  EXPECT_EQ(rotate90(top_left, d), Code{1} << cell_bit(d, 0, d - 1));
}

TEST(Bits, FourRotationsAreTheIdentity) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Code w = rng() & low_mask(36);
    EXPECT_EQ(rotate(w, 6, 4), w);
    EXPECT_EQ(rotate(w, 6, 3), rotate90(rotate90(rotate90(w, 6), 6), 6));
    EXPECT_EQ(std::popcount(rotate90(w, 6)), std::popcount(w));
  }
}

TEST(Bits, HammingWithRotationsIsTheMinimumOverRotations) {
  const Code a = 0x123456789, b = rotate(a, 6, 3) ^ 0b101;  // a rotated, two bits flipped
  EXPECT_EQ(hamming_with_rotations(a, b, 6), 2);
  EXPECT_GT(hamming(a, b), 2);
}

TEST(Bits, SelfRotationDistanceOfSymmetricPatternsIsZero) {
  EXPECT_EQ(self_rotation_distance(0, 6), 0);
  EXPECT_EQ(self_rotation_distance(low_mask(36), 6), 0);
  // The centre cell of a 3x3 payload is fixed by rotation: only it set -> symmetric.
  EXPECT_EQ(self_rotation_distance(Code{1} << cell_bit(3, 1, 1), 3), 0);
  // One corner cell set: each rotation moves it to another corner, distance 2.
  EXPECT_EQ(self_rotation_distance(Code{1} << cell_bit(3, 0, 0), 3), 2);
}

}  // namespace test_bits
