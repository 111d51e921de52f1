#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "code_experiments.hpp"
#include "codes/families.hpp"
#include "generator_speed.hpp"

namespace test_code_experiments {

using namespace tagbench;
using namespace tagbench::bench;

TEST(CodeExperiments, HammingBallVolumes) {
  EXPECT_EQ(hamming_ball_volume(36, 0), 1);
  EXPECT_EQ(hamming_ball_volume(36, 1), 37);
  EXPECT_EQ(hamming_ball_volume(36, 2), 667);
  EXPECT_EQ(hamming_ball_volume(36, 5), 443704);
  EXPECT_EQ(hamming_ball_volume(16, 16), 65536);
}

TEST(CodeExperiments, FalsePositiveTheoryFollowsTheFamilySizes) {
  const auto rows = fp_theory();
  ASSERT_FALSE(rows.empty());
  int seen36h15 = 0;
  for (const auto& r : rows) {
    const TagFamily& f = builtin_family(r.family);
    EXPECT_EQ(r.codes, f.size());
    EXPECT_EQ(r.correctable, r.bits_corrected <= (f.min_hamming() - 1) / 2);
    const double expected = 100.0 * 4 * static_cast<double>(f.size()) * hamming_ball_volume(36, r.bits_corrected) /
                            std::ldexp(1.0, 36);
    EXPECT_NEAR(r.fp_percent, expected, expected * 1e-12);
    EXPECT_NEAR(r.fp_percent_one_rotation * 4, r.fp_percent, r.fp_percent * 1e-12);
    if (r.family == "36h10" && r.bits_corrected >= 1 && r.bits_corrected <= 5) {
      // The paper's 36h10 column implies about 765 accepted words, not 4 x 2221 or 4 x 2320.
      ASSERT_TRUE(r.paper_implied_words.has_value());
      EXPECT_GT(*r.paper_implied_words, 700);
      EXPECT_LT(*r.paper_implied_words, 800);
    }
    if (r.family == "36h10") {
      EXPECT_EQ(r.paper_fp_percent.has_value(), r.bits_corrected <= 5);
    }
    seen36h15 += r.family == "36h15";
  }
  EXPECT_EQ(seen36h15, 8);
  const std::string csv = fp_theory_csv(rows);
  EXPECT_EQ(csv.rfind("family,codes,bits,min_hamming,bits_corrected,status", 0), 0u);
  const auto names = builtin_family_names();
  if (std::find(names.begin(), names.end(), "36h10") != names.end()) {
    EXPECT_NE(csv.find("N/A: beyond floor((h-1)/2)"), std::string::npos);  // 36h10 corrects at most 4
  }
}

TEST(CodeExperiments, CodeTableHasThePapersRowsWithMeasuredDistances) {
  const auto rows = code_table(2);
  ASSERT_EQ(rows.size(), paper_code_schemes().size());
  const auto shipped = builtin_family_names();
  for (const auto& r : rows) {
    const bool is_shipped = std::find(shipped.begin(), shipped.end(), r.scheme.family) != shipped.end();
    EXPECT_EQ(r.available, is_shipped) << r.scheme.family;
    if (!r.available) continue;
    std::uint64_t pairs = 0;
    for (const auto n : r.histogram) pairs += n;
    EXPECT_EQ(pairs, r.codes * (r.codes - 1) / 2) << r.scheme.family;
    EXPECT_LE(r.min_hamming_rotations, r.min_hamming_plain);
    if (r.scheme.family == "artoolkitplus-simple") {
      EXPECT_EQ(r.min_hamming_rotations, 4);
    }
    if (r.scheme.family == "artoolkitplus-bch") {
      EXPECT_EQ(r.min_hamming_rotations, 2);
    }
    if (r.scheme.family == "artag-2046") {
      EXPECT_EQ(r.codes, 2046u);
      EXPECT_EQ(r.min_hamming_rotations, 4);
    }
    if (r.scheme.family == "16h5") {
      EXPECT_EQ(r.codes, 30u);
      EXPECT_GE(r.min_hamming_rotations, 5);
    }
  }
  const std::string csv = code_table_csv(rows), fig5 = fig5_csv(rows);
  EXPECT_EQ(csv.rfind("scheme,family,status,bits,codes,min_hamming_with_rotations", 0), 0u);
  EXPECT_NE(csv.find("\"ARToolkit+ (BCH)\",artoolkitplus-bch,ok,36,4096,2,"), std::string::npos);
  EXPECT_EQ(fig5.rfind("scheme,family,codes,pairs_total,distance,pairs,fraction", 0), 0u);
}

// The generator runs recorded in the shipped family files: every seeded family's total and run lines
// are read back (the full candidate space, its wall time, threads, scan and CPU).
TEST(GeneratorSpeed, RecordedRunsOfEveryShippedGeneratedFamily) {
  const auto rows = tagbench::bench::recorded_generator_runs();
  std::set<std::string> names;
  for (const auto& r : rows) {
    names.insert(r.family);
    EXPECT_EQ(r.source, "recorded");
    EXPECT_EQ(r.candidates, std::ldexp(1.0, r.bits)) << r.family << ": a finished run scans every candidate";
    EXPECT_GT(r.wall_seconds, 0) << r.family;
    EXPECT_GE(r.threads, 1) << r.family;
    EXPECT_FALSE(r.scan.empty()) << r.family;
    EXPECT_FALSE(r.cpu.empty()) << r.family;
    EXPECT_EQ(r.codes, tagbench::builtin_family(r.family).size());
  }
  for (const char* f : {"16h5", "25h9", "36h9", "36h10", "36h11", "36h15"}) EXPECT_TRUE(names.count(f)) << f;
}

}  // namespace test_code_experiments
