#pragma once
// The paper's false-positive experiments on natural images (section VI-A), scored from a corpus'
// candidate store (corpus_tools/candidates.hpp): every candidate quad's payload bits, read once, are
// decoded against each family; a quad whose bits decode within k bits is a false positive, since the
// corpus holds no tags.
//   Fig. 6: ten 25h9 families generated with minimum complexity 1..10 (complexity_families), k = 0..4.
//   Fig. 7: the rival codebooks beside 36h10, 36h15 and 36h11 (fig7_schemes).
// Every rate comes with its counts and a 95 % Wilson interval, and with the rate a random payload
// would have: 4 N V(n, k) / 2^n (N codes, 4 rotations, V the Hamming ball's volume), exact while the
// balls are disjoint (2k < h) and an upper bound after that.
#include <cstdint>
#include <string>
#include <vector>

#include "candidates.hpp"
#include "codes/tag_family.hpp"
#include "stats.hpp"

namespace tagbench::bench {

struct ScoredFamily {
  std::string scheme;  // as the paper names it, e.g. "ARToolkit+ (BCH)" or "25h9, complexity >= 3"
  TagFamily family;
  double generation_seconds = 0;  // generated for the experiment (Fig. 6); 0 for shipped families
};

// 25h9 (or bits/h) generated with our lexicode generator for min complexity lo..hi, each with the
// original's default seed n*10000 + h*100 + complexity; `threads` for the generator.
std::vector<ScoredFamily> complexity_families(int bits = 25, int min_hamming = 9, int lo = 1, int hi = 10,
                                              int threads = 0);

// ARToolkit+ simple, ARToolkit+ BCH, ARTag (2046), 36h10, 36h15 and 36h11: the built-in families.
std::vector<ScoredFamily> fig7_schemes();

struct CodeCurveRow {
  std::string scheme, family;
  int bits = 0, min_hamming = 0, min_complexity = 0;
  std::size_t codes = 0;
  std::string subset;  // "all", "still" or "video-frame"
  int bits_corrected = 0;
  std::uint64_t quads = 0, accepted = 0;
  double rate = 0;
  Interval ci;
  double theory_rate = 0;     // a random payload's rate (above), capped at 1
  bool theory_exact = false;  // 2k < h: the union bound is the exact rate
  double generation_seconds = 0;
};

// For every family, subset and k = 0..min(max_k, bits): the store's quads of the family's payload
// width (the store must carry its image index for the subsets) and those accepted.
std::vector<CodeCurveRow> code_curves(const corpus::CandidateStore& store, const std::vector<ScoredFamily>& families,
                                      int max_k, int jobs = 0);

// 4 N V(n, k) / 2^n, capped at 1.
double random_payload_rate(std::size_t codes, int bits, int k);

std::string code_curves_csv(const std::vector<CodeCurveRow>& rows);

}  // namespace tagbench::bench
