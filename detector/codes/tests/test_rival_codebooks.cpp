#include <gtest/gtest.h>

#include <algorithm>

#include "codes/families.hpp"
#include "codes/rival_codebooks.hpp"
#include "codes/tag_family.hpp"

namespace test_rival_codebooks {

using namespace tagbench;

namespace {
// FNV-1a of the sorted, de-duplicated codebook, 8 little-endian bytes per code. The expected values
// were computed once from the lists in shared/reference/ (artoolkitplus_simple_512.txt,
// artoolkitplus_bch_4096.txt, artag_codes_from_aruco_1024.txt, whose 1024 entries hold 1023
// distinct words).
std::uint64_t sorted_checksum(std::vector<Code> c) {
  std::sort(c.begin(), c.end());
  c.erase(std::unique(c.begin(), c.end()), c.end());
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const Code v : c)
    for (int i = 0; i < 8; ++i) h = (h ^ ((v >> (8 * i)) & 0xff)) * 0x100000001b3ULL;
  return h;
}
}  // namespace

TEST(RivalCodebooks, ArtoolkitPlusSimpleMatchesTheReferenceList) {
  const auto c = artoolkitplus_simple_codes();
  ASSERT_EQ(c.size(), 512u);
  EXPECT_EQ(c[0], 0x6dc269c27u);
  EXPECT_EQ(c[1], 0x6d4229e26u);
  EXPECT_EQ(sorted_checksum(c), 0x918819f2616c4ae5ULL);
}

TEST(RivalCodebooks, ArtoolkitPlusBchMatchesTheReferenceList) {
  const auto c = artoolkitplus_bch_codes();
  ASSERT_EQ(c.size(), 4096u);
  EXPECT_EQ(c[1], 0x8f9d0a027u);
  EXPECT_EQ(sorted_checksum(c), 0x7c747d8558d658e5ULL);
}

TEST(RivalCodebooks, BchCodewordsAreMultiplesOfTheGenerator) {
  for (Code id = 0; id < 4096; ++id) {
    Code r = (id << 24) | bch_36_12_parity(id);
    for (int bit = 35; bit >= 24; --bit)
      if (r >> bit & 1) r ^= Code{0x1db2777} << (bit - 24);
    ASSERT_EQ(r, 0u) << id;
  }
}

TEST(RivalCodebooks, ArtagMatchesTheReferenceList) {
  const auto c = artag_codes(false);
  ASSERT_EQ(c.size(), 1023u);
  EXPECT_EQ(sorted_checksum(c), 0x5627c60af94072e5ULL);
  // Linear: the XOR of two words is a word.
  const std::vector<Code> sorted = [&] { auto s = c; std::sort(s.begin(), s.end()); return s; }();
  EXPECT_TRUE(std::binary_search(sorted.begin(), sorted.end(), c[5] ^ c[700]));
  const auto both = artag_codes(true);
  ASSERT_EQ(both.size(), 2046u);
  EXPECT_EQ(both[1023], c[0] ^ low_mask(36));
}

TEST(RivalCodebooks, MinimumDistancesAsMeasured) {
  // docs/paper-to-code.md section 3: simple 4, BCH 2, ARTag 4 (with rotations).
  const std::pair<const char*, int> expected[] = {
      {"artoolkitplus-simple", 4}, {"artoolkitplus-bch", 2}, {"artag", 4}};
  for (const auto& [name, h] : expected) {
    const TagFamily& f = builtin_family(name);
    EXPECT_EQ(distance_stats(f.codes(), 6, 2).min_with_rotations, h) << name;
    EXPECT_EQ(f.min_hamming(), h) << name;
  }
}

}  // namespace test_rival_codebooks
