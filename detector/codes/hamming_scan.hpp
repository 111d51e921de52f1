#pragma once
// Linear scans of a word list for near words: the inner loop of both the lexicode generator and
// the decoder. Uses AVX-512 VPOPCNTDQ (8 words per instruction) when the CPU has it, chosen at run
// time, else the POPCNT instruction, else portable scalar popcount; all give identical answers.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "bits.hpp"

namespace tagbench {

// Index of the first word w with hamming(v, w) <= max_distance, or -1.
std::ptrdiff_t first_within(std::span<const Code> words, Code v, int max_distance);

struct NearestWord {
  std::ptrdiff_t index = -1;  // first word at the minimum distance; -1 if none within the limit
  int distance = 65;
};

// The nearest word with hamming(v, w) <= max_distance (lowest index among ties), or index -1.
NearestWord nearest_within(std::span<const Code> words, Code v, int max_distance);

// Words grouped by their top t bits, for "is any word within max_distance of v?" when most queries
// have an answer: buckets are scanned in order of increasing prefix distance from v, where a near word
// is far more likely (for 36h9, a word sharing v's 8-bit prefix is ~27x likelier to be within 8 bits),
// so the early exit comes sooner; buckets whose prefix alone is farther than max_distance are skipped.
// The answer is exactly that of first_within over all words.
class PrefixBuckets {
 public:
  PrefixBuckets() = default;
  // bits: word width; t is chosen so that buckets hold about `target` words.
  PrefixBuckets(std::span<const Code> words, int bits, std::size_t target = 32);
  bool any_within(Code v, int max_distance) const { return first_word_within(v, max_distance).has_value(); }
  // A word within max_distance of v (the first found, not necessarily the nearest), if any.
  std::optional<Code> first_word_within(Code v, int max_distance) const;
  int prefix_bits() const { return t_; }

 private:
  int t_ = 0, shift_ = 0;
  std::vector<Code> sorted_;
  std::vector<std::uint32_t> offsets_;   // bucket b is sorted_[offsets_[b], offsets_[b+1])
  std::vector<std::uint32_t> masks_;     // prefix XOR masks, by increasing popcount
  std::vector<std::uint8_t> mask_pop_;
};

// Words indexed by c chunks of their bits (multi-index hashing): a word within m < c bits of v equals
// v exactly on at least one chunk (c chunks cannot all hold one of m differing bits), so only the
// words sharing one of v's c chunk values are compared. For a 36-bit family of 2348 words and m = 3
// (4 chunks of 9 bits) that is about 18 words instead of all of them.
class ChunkIndex {
 public:
  ChunkIndex() = default;
  // bits: word width (1..64); chunks: 1..bits, at most 20 bits a chunk (else no index: chunks() 0).
  // The index keeps the words' positions, not the words.
  ChunkIndex(std::span<const Code> words, int bits, int chunks);
  int chunks() const { return static_cast<int>(lo_.size()); }
  // nearest_within(words, v, max_distance) exactly (the same index and distance), for the words the
  // index was built from; max_distance >= chunks() scans every word.
  NearestWord nearest_within(std::span<const Code> words, Code v, int max_distance) const;

 private:
  std::vector<std::uint8_t> lo_, width_;                  // chunk j: bits [lo_[j], lo_[j] + width_[j])
  std::vector<std::vector<std::uint32_t>> offsets_;       // per chunk: bucket b is entries [b], [b + 1])
  std::vector<std::vector<std::uint32_t>> entries_;       // per chunk: word positions, ascending per bucket
};

// Name of the scan implementation in use ("avx512-vpopcntdq" or "scalar"), for benchmark records.
const char* hamming_scan_impl();

}  // namespace tagbench
