// FNV-1a: the published test vectors (the values are written into cache keys and store files, so
// they must never change), and the 32-bit variant the owner tags use.
#include <gtest/gtest.h>

#include <string>

#include "tools/hash.hpp"

namespace test_hash {

using tagbench::fnv1a32;
using tagbench::fnv1a64;

TEST(Hash, Fnv1a64MatchesThePublishedVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);  // the offset basis
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
}

TEST(Hash, Fnv1a32MatchesThePublishedVectors) {
  EXPECT_EQ(fnv1a32(""), 0x811c9dc5u);
  EXPECT_EQ(fnv1a32("a"), 0xe40c292cu);
  EXPECT_EQ(fnv1a32("foobar"), 0xbf9cf968u);
}

TEST(Hash, EveryByteCountsIncludingHighAndNulBytes) {
  const std::string with_nul("a\0b", 3), without("ab");
  EXPECT_NE(fnv1a64(with_nul), fnv1a64(without));
  EXPECT_NE(fnv1a64("\xff"), fnv1a64("\x7f"));
  EXPECT_NE(fnv1a32("ab"), fnv1a32("ba"));
}

}  // namespace test_hash
