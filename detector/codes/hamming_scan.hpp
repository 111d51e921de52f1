#pragma once
// Linear scans of a word list for near words: the inner loop of both the lexicode generator and
// the decoder. Uses AVX-512 VPOPCNTDQ (8 words per instruction) when the CPU has it, chosen at run
// time, else scalar popcount; both give identical answers.
#include <cstddef>
#include <span>

#include "codes/bits.hpp"

namespace tagbench {

// Index of the first word w with hamming(v, w) <= max_distance, or -1.
std::ptrdiff_t first_within(std::span<const Code> words, Code v, int max_distance);

struct NearestWord {
  std::ptrdiff_t index = -1;  // first word at the minimum distance; -1 if none within the limit
  int distance = 65;
};

// The nearest word with hamming(v, w) <= max_distance (lowest index among ties), or index -1.
NearestWord nearest_within(std::span<const Code> words, Code v, int max_distance);

// Name of the scan implementation in use ("avx512-vpopcntdq" or "scalar"), for benchmark records.
const char* hamming_scan_impl();

}  // namespace tagbench
