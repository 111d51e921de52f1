#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <random>

#include "codes/families.hpp"
#include "codes/tag_family.hpp"

namespace test_tag_family {

using namespace tagbench;

namespace {
FamilyInfo info(const std::string& name, int bits, int h) {
  FamilyInfo i;
  i.name = name;
  i.bits = bits;
  i.min_hamming = h;
  return i;
}
}  // namespace

TEST(TagFamily, DecodesEveryCodeInEveryRotation) {
  const TagFamily& f = builtin_family("36h11");
  for (std::size_t id = 0; id < f.size(); ++id)
    for (int r = 0; r < 4; ++r) {
      const auto d = f.decode(rotate(f.codes()[id], 6, r), 0);
      ASSERT_TRUE(d.has_value());
      EXPECT_EQ(d->id, static_cast<int>(id));
      EXPECT_EQ(d->rotation, r);
      EXPECT_EQ(d->hamming, 0);
    }
}

TEST(TagFamily, CorrectsUpToMaxAndNoFurther) {
  for (const char* name : {"25h7", "36h15", "36h11"}) {
    const TagFamily& f = builtin_family(name);
    const int d = f.payload_width(), n = f.bits(), t = (f.min_hamming() - 1) / 2;
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < 300; ++trial) {
      const int id = static_cast<int>(rng() % f.size()), r = static_cast<int>(rng() % 4);
      const int errors = static_cast<int>(rng() % static_cast<unsigned>(t + 1));
      Code w = rotate(f.codes()[static_cast<std::size_t>(id)], d, r);
      std::vector<int> cells(static_cast<std::size_t>(n));
      std::iota(cells.begin(), cells.end(), 0);
      std::shuffle(cells.begin(), cells.end(), rng);
      for (int e = 0; e < errors; ++e) w ^= Code{1} << cells[static_cast<std::size_t>(e)];
      for (int k = 0; k <= t; ++k) {
        const auto dec = f.decode(w, k);
        if (errors <= k) {
          ASSERT_TRUE(dec.has_value()) << name << " errors " << errors << " max " << k;
          EXPECT_EQ(dec->id, id);
          EXPECT_EQ(dec->rotation, r);
          EXPECT_EQ(dec->hamming, errors);
        } else {
          // Every other code is at least h - errors > t >= k away, so nothing is within k.
          EXPECT_FALSE(dec.has_value()) << name << " errors " << errors << " max " << k;
        }
      }
    }
  }
}

TEST(TagFamily, BeyondHalfTheDistanceTakesTheNearest) {
  const TagFamily& f = builtin_family("16h5");
  // With max_corrected >= h/2 a word can be near two codes; the nearest must win.
  std::mt19937_64 rng(9);
  for (int trial = 0; trial < 2000; ++trial) {
    const Code w = rng() & low_mask(16);
    const auto d = f.decode(w, 4);
    int best = 99;
    for (const Code c : f.codes()) best = std::min(best, hamming_with_rotations(w, c, 4));
    if (best <= 4) {
      ASSERT_TRUE(d.has_value());
      EXPECT_EQ(d->hamming, best);
      EXPECT_EQ(hamming(w, rotate(f.codes()[static_cast<std::size_t>(d->id)], 4, d->rotation)), best);
    } else {
      EXPECT_FALSE(d.has_value());
    }
  }
}

// 36h11 (2348 words: decoded through the chunk index) at every limit up to 7 bits, near and beyond
// half its distance: the nearest word, the lowest id and rotation among ties, as a scan of all words.
TEST(TagFamily, DecodesAsAScanOfEveryWord) {
  const TagFamily& f = builtin_family("36h11");
  const auto words = f.rotated_words();
  std::mt19937_64 rng(17);
  int decoded = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    Code w = words[rng() % words.size()];
    const int flips = static_cast<int>(rng() % 9);
    for (int e = 0; e < flips; ++e) w ^= Code{1} << (rng() % 36);
    const int k = 1 + static_cast<int>(rng() % 7);
    int best = 99;
    std::size_t at = 0;
    for (std::size_t i = 0; i < words.size(); ++i)
      if (const int d = hamming(w, words[i]); d < best) best = d, at = i;
    const auto dec = f.decode(w, k);
    ASSERT_EQ(dec.has_value(), best <= k) << trial;
    if (!dec) continue;
    ++decoded;
    EXPECT_EQ(dec->hamming, best);
    EXPECT_EQ(dec->id, static_cast<int>(at / 4));
    EXPECT_EQ(dec->rotation, static_cast<int>(at % 4));
    EXPECT_EQ(f.nearest_word(w, k).index, static_cast<std::ptrdiff_t>(at));
  }
  EXPECT_GT(decoded, 1000);
}

TEST(TagFamily, RejectsBadFamilies) {
  EXPECT_THROW(TagFamily(info("x", 20, 3), {1, 2}), std::invalid_argument);       // bits not a square
  EXPECT_THROW(TagFamily(info("x", 81, 3), {1, 2}), std::invalid_argument);       // over 64
  EXPECT_THROW(TagFamily(info("x", 16, 17), {1, 2}), std::invalid_argument);      // h larger than bits
  EXPECT_THROW(TagFamily(info("x", 16, 1), {0x231b, 0x231b}), std::invalid_argument);  // duplicate
  EXPECT_THROW(TagFamily(info("x", 16, 1), {0x1ffff}), std::invalid_argument);    // more than 16 bits
  EXPECT_THROW(TagFamily(info("x", 16, 1), {}), std::invalid_argument);           // empty
  // 0x231b and a rotation of it with one bit flipped are 1 apart: h = 5 must be refused.
  EXPECT_THROW(TagFamily(info("x", 16, 5), {0x231b, rotate90(0x231b, 4) ^ 1}), std::invalid_argument);
  // A code closer than h to its own rotation.
  EXPECT_THROW(TagFamily(info("x", 16, 5), {0x0}), std::invalid_argument);
}

TEST(TagFamily, DistanceStatsOfAKnownFamily) {
  const TagFamily& f = builtin_family("36h11");
  const DistanceStats s = distance_stats(f.codes(), 6, 2);
  EXPECT_EQ(s.min_with_rotations, 11);
  EXPECT_GE(s.min_plain, 11);
  std::uint64_t pairs = 0;
  for (const auto n : s.histogram) pairs += n;
  EXPECT_EQ(pairs, f.size() * (f.size() - 1) / 2);
  for (int k = 0; k < 11; ++k) EXPECT_EQ(s.histogram[static_cast<std::size_t>(k)], 0u);
}

TEST(Families, RegistryKnowsAllShippedAndRivalFamilies) {
  const auto names = builtin_family_names();
  for (const char* n : {"16h5", "25h7", "25h9", "36h15", "artoolkitplus-simple", "artoolkitplus-bch", "artag",
                        "artag-2046"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  EXPECT_EQ(&builtin_family("tag16h5"), &builtin_family("16h5"));
  EXPECT_EQ(canonical_family_name("tag36h11"), "36h11");
  EXPECT_EQ(canonical_family_name("36h11"), "36h11");
  EXPECT_EQ(canonical_family_name("artoolkitplus-bch"), "artoolkitplus-bch");
  EXPECT_EQ(canonical_family_name("tag"), "tag");
  EXPECT_EQ(canonical_family_name("tagged.fam"), "tagged.fam");  // only "tag" before a digit goes
  EXPECT_THROW(builtin_family("36h99"), std::invalid_argument);
  EXPECT_THROW(load_family("/no/such/file.fam"), std::invalid_argument);
  try {  // a folder given for a family file is named as one
    load_family(std::filesystem::temp_directory_path().string() + "/");
    ADD_FAILURE() << "a directory loaded as a family";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(": is a directory"), std::string::npos) << e.what();
  }
}

TEST(TagFamily, MaxPayloadWidthIsTheWidestFamilys) {
  const std::vector<TagFamily> none;
  EXPECT_EQ(max_payload_width(none), 0);
  const std::vector<TagFamily> small{load_family("16h5"), load_family("25h9")};
  EXPECT_EQ(max_payload_width(small), 5);
  const std::vector<TagFamily> mixed{load_family("25h9"), load_family("36h11"), load_family("16h5")};
  EXPECT_EQ(max_payload_width(mixed), 6);
}

}  // namespace test_tag_family
