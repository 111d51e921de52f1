#pragma once
// The paper's code experiments (section V): the encoding table, Fig. 5 (distances between all
// pairs of codewords) and the theoretical false-positive table. Pure functions of the families;
// `tagbench codes` writes them as CSV.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tagbench::bench {

// A row of the experiments: a scheme as the paper names it and our family that implements it.
struct CodeScheme {
  std::string scheme;   // e.g. "ARToolkit+ (simple)"
  std::string family;   // built-in family name, e.g. "artoolkitplus-simple"
  std::optional<int> paper_codes, paper_min_hamming;  // the paper's table, where it lists the scheme
};
// The schemes of the paper's table plus 36h11, 25h9 and 16h5.
std::vector<CodeScheme> paper_code_schemes();

struct CodeTableRow {
  CodeScheme scheme;
  bool available = false;  // false while the family's generator run is still in progress
  int bits = 0;
  std::size_t codes = 0;
  int min_hamming_rotations = 0, min_hamming_plain = 0, min_complexity = 0;
  std::vector<std::uint64_t> histogram;  // Fig. 5: pairs at each distance (minimum over rotations)
};
std::vector<CodeTableRow> code_table(int threads = 0);

struct FpTheoryRow {
  std::string family;
  std::size_t codes = 0;
  int bits = 0, min_hamming = 0, bits_corrected = 0;
  bool correctable = false;            // bits_corrected <= floor((h-1)/2): the balls are disjoint
  double words_accepted = 0;           // 4 * codes * sum_{i<=k} C(n, i): all rotations counted
  double fp_percent = 0;               // 100 * words_accepted / 2^n
  double fp_percent_one_rotation = 0;  // the same with one rotation per code (a quad of known orientation)
  std::optional<double> paper_fp_percent;
  std::optional<double> paper_implied_words;  // paper % / 100 * 2^n / sum_{i<=k} C(n, i)
};
// 36h10 and 36h15, 0..7 bits corrected, from the real family sizes (a family whose generator run is
// still in progress is left out).
std::vector<FpTheoryRow> fp_theory();

std::string code_table_csv(const std::vector<CodeTableRow>& rows);
std::string fig5_csv(const std::vector<CodeTableRow>& rows);
std::string fp_theory_csv(const std::vector<FpTheoryRow>& rows);

// sum_{i=0}^{k} C(n, i), exactly in double for n <= 64.
double hamming_ball_volume(int n, int k);

}  // namespace tagbench::bench
