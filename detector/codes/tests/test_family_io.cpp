#include <gtest/gtest.h>

#include <fstream>

#include "codes/families.hpp"
#include "codes/family_io.hpp"

namespace test_family_io {

using namespace tagbench;

namespace {
const char* kGood = R"(# a comment
name: mini
bits: 16
hamming: 5
complexity: 5
seed: 160505
order: prime
generator: tagbench-lexicode 1
count: 3
0x231b
2ea5
0x346a
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

void expect_error(const std::string& text, const std::string& fragment) {
  try {
    parse_family(text, "in.fam");
    FAIL() << "accepted: " << fragment;
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("in.fam"), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
}
}  // namespace

TEST(FamilyIo, ParsesAndRoundTrips) {
  const TagFamily f = parse_family(kGood, "in.fam");
  EXPECT_EQ(f.name(), "mini");
  EXPECT_EQ(f.size(), 3u);
  EXPECT_EQ(f.codes()[1], 0x2ea5u);
  EXPECT_EQ(f.info().seed.value(), 160505);
  const TagFamily g = parse_family(format_family(f, {"a record"}), "again");
  EXPECT_EQ(g.codes(), f.codes());
  EXPECT_EQ(g.info().generator, f.info().generator);
  EXPECT_EQ(g.min_hamming(), 5);
}

TEST(FamilyIo, EveryBuiltInFamilyRoundTrips) {
  for (const auto& n : builtin_family_names()) {
    const TagFamily& f = builtin_family(n);
    EXPECT_EQ(parse_family(format_family(f), n).codes(), f.codes()) << n;
  }
}

TEST(FamilyIo, BadFilesAreRefusedWithTheProblemNamed) {
  expect_error(replace(kGood, "2ea5", "2eg5"), ":11: not a hex code");
  expect_error(replace(kGood, "count: 3", "count: 4"), "count 4 but the file has 3");
  expect_error(replace(kGood, "2ea5", "0x231b"), "duplicate code 0x231b");
  expect_error(replace(kGood, "hamming: 5", "hamming: 9"), "closer than h=9");
  expect_error(replace(kGood, "bits: 16", "bits: 20"), "not a square");
  expect_error(replace(kGood, "bits: 16", "bits: 100"), "over 64");
  expect_error(replace(kGood, "hamming: 5", "hamming: 17"), "hamming 17 is outside 1..bits (16)");
  expect_error(replace(kGood, "hamming: 5", "hamming: -5"), "hamming -5 is outside 1..bits (16)");
  expect_error(replace(kGood, "hamming: 5", "hamming: 0"), "hamming 0 is outside 1..bits (16)");
  expect_error(replace(kGood, "complexity: 5", "complexity: 99"), "complexity 99 is outside 0..bits (16)");
  expect_error(replace(kGood, "complexity: 5", "complexity: -3"), "complexity -3 is outside 0..bits (16)");
  expect_error(replace(kGood, "name: mini", "name: "), "the name is empty");
  expect_error(replace(kGood, "name: mini\n", ""), "missing header key 'name'");
  expect_error(replace(kGood, "seed: 160505", "colour: blue"), "unknown header key 'colour'");
  expect_error(replace(kGood, "hamming: 5", "hamming: five"), "'hamming' is not an integer");
  // 2^32 + 16 once wrapped to a valid 16 (found by fuzz/fuzz_family.cpp).
  expect_error(replace(kGood, "bits: 16", "bits: 4294967312"), "'bits' is out of range: 4294967312");
  expect_error(replace(kGood, "count: 3", "count: 3\nstatus: partial"), "not a family");
}

TEST(FamilyIo, CppFormatListsEveryCode) {
  const TagFamily f = parse_family(kGood, "in.fam");
  const std::string cpp = format_family_cpp(f);
  EXPECT_NE(cpp.find("tagmini_codes[3]"), std::string::npos);
  for (const char* c : {"0x231bULL", "0x2ea5ULL", "0x346aULL"}) EXPECT_NE(cpp.find(c), std::string::npos) << c;
}

TEST(FamilyIo, HexParsing) {
  EXPECT_EQ(parse_hex_code("0x1F").value(), 0x1fu);
  EXPECT_EQ(parse_hex_code("ffffffffffffffff").value(), ~Code{0});
  EXPECT_FALSE(parse_hex_code("1ffffffffffffffff"));
  EXPECT_FALSE(parse_hex_code("0x"));
  EXPECT_FALSE(parse_hex_code("12 34"));
}

// Checkpoints (`family generate --resume`): every error names the file on one line, and no number
// wraps into a valid-looking one (findings of fuzz/fuzz_family.cpp; inputs in fuzz/regressions/family).
TEST(FamilyIo, BadCheckpointsAreRefusedWithTheFileNamed) {
  LexicodeParams p;
  p.bits = 16;
  p.min_hamming = 5;
  p.min_complexity = 5;
  LexicodeState s;
  s.next_index = 1234;
  s.codes = {0x231b, 0x2ea5};
  s.elapsed_seconds = 1.5;
  const std::string good = format_checkpoint(p, s);
  const std::string path = ::testing::TempDir() + "/family_io_bad.ckpt";
  const auto read = [&](const std::string& text) {
    std::ofstream(path, std::ios::trunc) << text;
    return read_checkpoint(path);
  };
  const Checkpoint ok = read(good);
  EXPECT_EQ(ok.state.next_index, s.next_index);
  EXPECT_DOUBLE_EQ(ok.state.elapsed_seconds, 1.5);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {replace(good, "order: prime", "order: primes"), "unknown candidate order 'primes'"},
      {replace(good, "bits: 16", "bits: 4294967312"), "'bits' is out of range"},
      {replace(good, "bits: 16", "bits: 20"), "not the square of a payload width"},
      {replace(good, "next_index: 1234", "next_index:"), "'next_index' is not an integer"},
      {replace(good, "next_index: 1234", "next_index: 340282366920938463463374607431768211457"),
       "'next_index' is out of range"},
      {replace(good, "elapsed_seconds: 1500e-3", "elapsed_seconds: 1e999"), "'elapsed_seconds' is not a number"},
      {replace(good, "elapsed_seconds: 1500e-3", "elapsed_seconds: 1e300"), "'elapsed_seconds' is not a number"},
      {replace(good, "elapsed_seconds: 1500e-3", "elapsed_seconds: -1"), "'elapsed_seconds' is not a number"},
  };
  for (const auto& [text, fragment] : bad) {
    try {
      read(text);
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path + ":", 0), 0u) << msg;  // "FILE: " or "FILE:LINE: "
      EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

}  // namespace test_family_io
