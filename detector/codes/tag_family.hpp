#pragma once
// A tag family: a set of d x d payload codes with a guaranteed minimum Hamming distance.
//
// Codes are in AprilTag 1 order (bits.hpp): MSB = top-left payload cell, row-major, 1 = white.
// The printed tag is (d+4) x (d+4) cells: a white ring, a black ring, then the payload; the "tag
// size" used for pose is the black square's edge, (d+2) cells.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "bits.hpp"
#include "hamming_scan.hpp"

namespace tagbench {

// Where a family comes from; all of it is written into family files.
struct FamilyInfo {
  std::string name;
  int bits = 0;             // n = d*d
  int min_hamming = 0;      // h: minimum distance between any two codes over all rotations
  int min_complexity = 0;   // the generator's threshold (generated families) or the measured minimum
  std::optional<std::int64_t> seed;  // generated families only
  std::string order;        // "prime", "lex", or "" for codebooks built from a specification
  std::string generator;    // e.g. "tagbench-lexicode 1", "spec artoolkitplus-simple"
  std::vector<std::string> records;  // the file's "# key: ..." comment lines (generation records), kept verbatim
};

struct DecodeResult {
  int id = -1;        // index into codes()
  int hamming = 0;    // bits corrected
  int rotation = 0;   // observed == rotate(code, d, rotation): clockwise quarter turns as printed
  bool operator==(const DecodeResult&) const = default;
};

class TagFamily {
 public:
  // Checks the codes against the info (range, no duplicates, and, when check_distance is set, no
  // two codes or rotations closer than min_hamming); throws std::invalid_argument naming the problem.
  TagFamily(FamilyInfo info, std::vector<Code> codes, bool check_distance = true);

  const FamilyInfo& info() const { return info_; }
  const std::string& name() const { return info_.name; }
  int bits() const { return info_.bits; }
  int payload_width() const { return d_; }
  int min_hamming() const { return info_.min_hamming; }
  const std::vector<Code>& codes() const { return codes_; }
  std::size_t size() const { return codes_.size(); }

  // The code nearest to `observed` over all ids and rotations if within max_corrected bits.
  // Ties (possible only when max_corrected > (h-1)/2) go to the lowest id, then lowest rotation.
  std::optional<DecodeResult> decode(Code observed, int max_corrected) const;

  // All four rotations of every code: entry 4*id + r is rotate(code[id], d, r).
  std::span<const Code> rotated_words() const { return words_; }

  // nearest_within(rotated_words(), observed, max_distance) for observed's low bits() bits (the rest
  // ignored, as decode does), through the chunk index when one fits.
  NearestWord nearest_word(Code observed, int max_distance) const;

 private:
  FamilyInfo info_;
  int d_ = 0;
  std::vector<Code> codes_;
  std::vector<Code> words_;
  std::unordered_map<Code, std::uint32_t> exact_;  // word -> 4*id + r, for the zero-error fast path
  PrefixBuckets buckets_;                          // words_ bucketed for the few-errors path
  // chunked_[c]: words_ indexed by c chunks (c = 3..8, chunks of 6 bits or more; families of 256
  // words or more): a search within m bits uses c = max(3, m + 1), else the scan of every word.
  std::vector<ChunkIndex> chunked_;
};

// The widest payload (d) among `families`; 0 for none. The quad stages that serve every family
// (the border pre-filter, the kink measure) size their rings for it.
inline int max_payload_width(std::span<const TagFamily> families) {
  int d = 0;
  for (const TagFamily& f : families) d = f.payload_width() > d ? f.payload_width() : d;
  return d;
}

// Distance statistics of a codebook (Fig. 5 and `family stats`).
struct DistanceStats {
  int min_plain = 0;             // min over pairs of hamming(a, b)
  int min_with_rotations = 0;    // min over pairs of hamming_with_rotations(a, b), and over each code's own rotations
  int min_self_rotation = 0;     // min over codes of self_rotation_distance
  std::vector<std::uint64_t> histogram;  // histogram[k] = pairs whose distance with rotations is k (0..bits)
};
DistanceStats distance_stats(std::span<const Code> codes, int d, int threads = 0);

// Measured minimum of rectangle_complexity over the codes.
int min_complexity_of(std::span<const Code> codes, int d);

}  // namespace tagbench
