#pragma once
// The rival 36-bit codebooks of the paper (Fig. 5, Fig. 7 and the encoding table), built from their
// specifications (docs/paper-to-code.md section 3), in AprilTag 1 order (bit 35 = top-left cell, 1 = white).
#include <vector>

#include "codes/bits.hpp"

namespace tagbench {

// ARToolKitPlus "simple" ids 0..511: the 9-bit id repeated four times, XORed with a fixed mask.
std::vector<Code> artoolkitplus_simple_codes();

// ARToolKitPlus BCH ids 0..4095: systematic BCH(36,12) (shortened BCH(63,39), generator 0x1db2777),
// codeword = id << 24 | (x^24 id(x) mod g(x)), XORed with a fixed mask.
std::vector<Code> artoolkitplus_bch_codes();
// The BCH parity of a 12-bit id (exposed for tests).
Code bch_36_12_parity(Code id);

// ARTag: the 1023 non-zero words of its linear [36,10] code; entry k is the word whose top ten bits
// (the systematic part) are k+1. With complements = true, the 1023 complements follow (ARTag's
// published 2046, which counts inverted-border markers).
std::vector<Code> artag_codes(bool with_complements);

}  // namespace tagbench
