#include "codes/rival_codebooks.hpp"

#include <array>

namespace tagbench {

std::vector<Code> artoolkitplus_simple_codes() {
  std::vector<Code> out;
  for (Code id = 0; id < 512; ++id) out.push_back((id | id << 9 | id << 18 | id << 27) ^ 0x6dc269c27ULL);
  return out;
}

Code bch_36_12_parity(Code id) {
  constexpr Code g = 0x1db2777;  // degree 24
  Code r = id << 24;             // x^24 id(x), degree < 36
  for (int bit = 35; bit >= 24; --bit)
    if (r >> bit & 1) r ^= g << (bit - 24);
  return r;  // degree < 24
}

std::vector<Code> artoolkitplus_bch_codes() {
  std::vector<Code> out;
  for (Code id = 0; id < 4096; ++id) out.push_back(((id << 24) | bch_36_12_parity(id)) ^ 0x8f80b8750ULL);
  return out;
}

std::vector<Code> artag_codes(bool with_complements) {
  constexpr std::array<Code, 10> basis = {0x8019813cc, 0x400cc09e6, 0x2006604f3, 0x1032e9d24, 0x081974e92,
                                          0x040cba749, 0x023784cf9, 0x012a1b921, 0x00a4d43cd, 0x0063b3ebb};
  std::vector<Code> out;
  for (Code id = 1; id < 1024; ++id) {
    Code w = 0;
    for (int i = 0; i < 10; ++i)
      if (id >> (9 - i) & 1) w ^= basis[static_cast<std::size_t>(i)];
    out.push_back(w);
  }
  if (with_complements)
    for (std::size_t k = 0; k < 1023; ++k) out.push_back(out[k] ^ low_mask(36));
  return out;
}

}  // namespace tagbench
