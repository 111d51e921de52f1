// Figs. 6 and 7 scoring on a store made here: records built from a family's own codes at known
// distances must be accepted exactly from that k on, per subset; the theoretical rate is the
// paper's formula; the complexity families are the generator's, with their thresholds honoured.
#include <gtest/gtest.h>

#include <random>

#include "codes/bits.hpp"
#include "codes/complexity.hpp"
#include "codes/families.hpp"
#include "code_experiments.hpp"
#include "fp_codes.hpp"

namespace test_fp_codes {

using namespace tagbench;
using namespace tagbench::bench;
using namespace tagbench::corpus;

namespace {

corpus::CandidateImage image(const std::string& file, const std::string& group, const std::string& kind) {
  corpus::CandidateImage i;
  i.file = file;
  i.group = group;
  i.kind = kind;
  return i;
}

// The word with its bits 0..n-1 flipped: n bits away.
Code flip_low(Code c, int n) { return c ^ ((Code{1} << n) - 1); }

}  // namespace

TEST(CodeCurves, CountsQuadsWithinKBitsPerSubset) {
  const TagFamily& f = builtin_family("25h9");
  CandidateStore store;
  store.images = {image("a.png", "g1", "still"), image("b.png", "g2", "video-frame")};
  // Image 0 (still): code 3 exact, code 4 rotated once with 2 bits off, a 6x6 record (not 25h9's).
  // Image 1 (video): code 7 with 4 bits off, and a word far from every code.
  auto rec = [](std::uint32_t image, int d, Code bits) {
    CandidateRecord r;
    r.image = image;
    r.d = static_cast<std::uint8_t>(d);
    r.bits = bits;
    return r;
  };
  store.records = {rec(0, 5, f.codes()[3]), rec(0, 5, flip_low(rotate90(f.codes()[4], 5), 2)),
                   rec(0, 6, f.codes()[3]), rec(1, 5, flip_low(f.codes()[7], 4))};
  // A far word: one whose nearest code is more than 4 away, found by search with a fixed seed.
  std::mt19937_64 rng(7);
  for (;;) {
    const Code w = rng() & ((Code{1} << 25) - 1);
    if (!f.decode(w, 4)) {
      store.records.push_back(rec(1, 5, w));
      break;
    }
  }
  const auto rows = code_curves(store, {{"25h9", f, 0}}, 4, 2);
  ASSERT_EQ(rows.size(), 3u * 5u);  // all, still, video-frame x k = 0..4
  auto at = [&](const std::string& subset, int k) {
    for (const auto& r : rows)
      if (r.subset == subset && r.bits_corrected == k) return r;
    ADD_FAILURE() << subset << " " << k;
    return CodeCurveRow{};
  };
  const std::uint64_t all_expected[5] = {1, 1, 2, 2, 3};
  for (int k = 0; k <= 4; ++k) {
    const auto a = at("all", k);
    EXPECT_EQ(a.quads, 4u);  // the 6x6 record is not a 25h9 quad
    EXPECT_EQ(a.accepted, all_expected[k]) << k;
    EXPECT_DOUBLE_EQ(a.rate, static_cast<double>(all_expected[k]) / 4);
    EXPECT_LE(a.ci.lo, a.rate);
    EXPECT_GE(a.ci.hi, a.rate);
    EXPECT_EQ(at("still", k).quads, 2u);
    EXPECT_EQ(at("still", k).accepted, k >= 2 ? 2u : 1u);
    EXPECT_EQ(at("video-frame", k).quads, 2u);
    EXPECT_EQ(at("video-frame", k).accepted, k >= 4 ? 1u : 0u);
    EXPECT_EQ(a.codes, 35u);
    EXPECT_TRUE(a.theory_exact);  // 2k < 9 up to k = 4
    EXPECT_DOUBLE_EQ(a.theory_rate, random_payload_rate(35, 25, k));
  }
  const std::string csv = code_curves_csv(rows);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "scheme,family,bits,min_hamming,min_complexity,codes,subset,bits_corrected,quads,accepted,rate,ci95_lo,"
            "ci95_hi,theory_rate,theory_exact,generation_seconds");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), rows.size() + 1);
}

TEST(CodeCurves, RefusesRecordsOfImagesTheIndexDoesNotHave) {
  CandidateStore store;
  CandidateRecord r;
  r.image = 3;
  r.d = 5;
  store.records = {r};
  EXPECT_THROW(code_curves(store, {{"25h9", builtin_family("25h9"), 0}}, 2), std::invalid_argument);
}

TEST(RandomPayloadRate, IsThePapersFormula) {
  // The paper's table (section V-B) lists 36h10 at 0.000041 % for 1 bit with its family size; with
  // N codes: 4 N (1 + 36) / 2^36.
  EXPECT_DOUBLE_EQ(random_payload_rate(2320, 36, 1), 4.0 * 2320 * 37 / std::ldexp(1.0, 36));
  EXPECT_DOUBLE_EQ(random_payload_rate(30, 16, 0), 120.0 / 65536);
  EXPECT_EQ(random_payload_rate(4096, 36, 9), 1.0);  // capped
}

TEST(ComplexityFamilies, AreTheGeneratorsFamiliesWithTheirThresholds) {
  // 16h5 at complexity 5 is the shipped 16h5 (the original's default threshold min(10, 16/3)).
  const auto fams = complexity_families(16, 5, 1, 6, 2);
  ASSERT_EQ(fams.size(), 6u);
  EXPECT_EQ(fams[4].family.codes(), builtin_family("16h5").codes());
  for (std::size_t i = 0; i < fams.size(); ++i) {
    const int c = static_cast<int>(i) + 1;
    EXPECT_EQ(fams[i].family.info().min_complexity, c);
    EXPECT_EQ(fams[i].family.info().seed, 160500 + c);
    EXPECT_GE(min_complexity_of(fams[i].family.codes(), 4), c);
    EXPECT_EQ(fams[i].scheme, "16h5, complexity >= " + std::to_string(c));
  }
  // A stricter threshold cannot admit a code of complexity below it: 16h5 with complexity 6 differs.
  EXPECT_NE(fams[5].family.codes(), fams[4].family.codes());
  EXPECT_THROW(complexity_families(16, 5, 3, 2), std::invalid_argument);
}

TEST(Fig7Schemes, AreThePapersFiveAnd36h11) {
  const auto s = fig7_schemes();
  ASSERT_EQ(s.size(), 6u);
  EXPECT_EQ(s[0].family.size(), 512u);
  EXPECT_EQ(s[1].family.size(), 4096u);
  EXPECT_EQ(s[2].family.size(), 2046u);
  EXPECT_EQ(s[3].family.name(), builtin_family("36h10").name());
  EXPECT_EQ(s[4].family.name(), builtin_family("36h15").name());
  EXPECT_EQ(s[5].family.name(), builtin_family("36h11").name());
}

}  // namespace test_fp_codes
