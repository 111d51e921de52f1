#pragma once
// Bit-level helpers of the coding system.
//
// Convention ("AprilTag 1 order"): a d x d payload is a word of d*d bits; the most significant bit
// (bit d*d-1) is the top-left payload cell, then row-major; a set bit is a white cell.
// So cell (row y, column x) is bit d*d-1-(y*d+x).
#include <bit>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tagbench {

using Code = std::uint64_t;

// The widest payload: d x d bits must fit in a Code (8 x 8 = 64). Families, the lexicode generator,
// the complexity tables and the payload reader all stop here.
inline constexpr int kMaxPayloadWidth = 8;

// "0x1f": how codes are written in family files and messages.
inline std::string hex_code(Code c) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%llx", static_cast<unsigned long long>(c));
  return buf;
}

// Decimal text of a 128-bit count (candidate indices of 64-bit payloads need 65 bits).
inline std::string to_decimal(unsigned __int128 v) {
  std::string s;
  do {
    s.insert(s.begin(), static_cast<char>('0' + static_cast<int>(v % 10)));
    v /= 10;
  } while (v);
  return s;
}

constexpr Code low_mask(int nbits) { return nbits >= 64 ? ~Code{0} : (Code{1} << nbits) - 1; }

constexpr int hamming(Code a, Code b) { return std::popcount(a ^ b); }

// Bit index of payload cell (row y, column x) in AprilTag 1 order.
constexpr int cell_bit(int d, int y, int x) { return d * d - 1 - (y * d + x); }

// Rotates a payload by 90 degrees clockwise as printed: the new top row is the old left column read
// bottom to top, i.e. rotated(y, x) = original(d-1-x, y). This is the original generator's rotate90
// (docs/paper-to-code.md section 2), so families built with it are bit-exact with the published ones.
constexpr Code rotate90(Code w, int d) {
  Code wr = 0;
  for (int r = d - 1; r >= 0; --r)
    for (int c = 0; c < d; ++c) wr = (wr << 1) | ((w >> (r + d * c)) & 1u);
  return wr;
}

// rotate90 applied k times (k taken modulo 4).
constexpr Code rotate(Code w, int d, int k) {
  for (int i = 0; i < (k & 3); ++i) w = rotate90(w, d);
  return w;
}

// Minimum over the four rotations r of b of hamming(a, rotate(b, r)).
constexpr int hamming_with_rotations(Code a, Code b, int d) {
  int best = hamming(a, b);
  for (int r = 1; r < 4; ++r) {
    b = rotate90(b, d);
    const int h = hamming(a, b);
    if (h < best) best = h;
  }
  return best;
}

// Minimum distance between the four rotations of one word (6 pairs; 0 for a symmetric pattern).
constexpr int self_rotation_distance(Code w, int d) {
  Code r[4] = {w, 0, 0, 0};
  for (int i = 1; i < 4; ++i) r[i] = rotate90(r[i - 1], d);
  int best = 64;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const int h = hamming(r[i], r[j]);
      if (h < best) best = h;
    }
  return best;
}

}  // namespace tagbench
