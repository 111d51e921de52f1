#pragma once
// The paper's modified lexicode generator (section V-A; recipe in docs/paper-to-code.md section 2).
//
// Candidates are visited in the order v_k = (V0 + k p) mod 2^n (p = 982451653, V0 from
// java.util.Random(seed).nextLong(), "prime" order) or 0, 1, 2, ... ("lex" order). A candidate is
// accepted when its four rotations are pairwise at least h apart, it is at least h from every
// rotation of every accepted code, and its rectangle complexity is at least the minimum. Greedy
// first fit, nothing else, so the defaults reproduce the published AprilTag families bit for bit.
//
// Parallelism never changes the answer: a block of candidates is tested by all threads against the
// codes accepted before the block, then the block's survivors are re-checked in order against the
// codes accepted earlier in the same block.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "codes/bits.hpp"
#include "codes/hamming_scan.hpp"

namespace tagbench {

enum class CandidateOrder { kPrime, kLex };

const char* to_string(CandidateOrder o);
CandidateOrder parse_candidate_order(const std::string& s);  // "prime" or "lex"; throws otherwise

inline constexpr std::uint64_t kLexicodePrime = 982451653;  // the paper's "large prime" p
inline constexpr int kGeneratorVersion = 1;

struct LexicodeParams {
  int bits = 36;             // n = d*d, d in 3..8
  int min_hamming = 11;      // h
  int min_complexity = -1;   // -1: the original default min(10, n/3)
  std::optional<std::int64_t> seed;  // empty: n*10000 + h*100 + complexity, as the original
  CandidateOrder order = CandidateOrder::kPrime;

  int payload_width() const;          // d
  int resolved_complexity() const;
  std::int64_t resolved_seed() const;
  void validate() const;              // throws std::invalid_argument with a one-line message
};

// Where a run stands: everything needed to continue it exactly (the checkpoint's content).
struct LexicodeState {
  unsigned __int128 next_index = 0;  // candidates 0 .. next_index-1 have been decided
  std::vector<Code> codes;           // accepted so far, in acceptance order
  double elapsed_seconds = 0;        // wall time spent so far, summed over resumed runs
};

struct LexicodeProgress {
  unsigned __int128 done = 0, total = 0;
  std::size_t codes = 0;
  double elapsed_seconds = 0;    // this run plus earlier runs
  double candidates_per_second = 0;  // in this run
};

class LexicodeGenerator {
 public:
  LexicodeGenerator(LexicodeParams params, LexicodeState start = {});

  // Candidate number k (0-based) in this run's order.
  Code candidate(unsigned __int128 k) const;
  unsigned __int128 total_candidates() const { return total_; }

  // Runs until every candidate is decided, max_codes codes are accepted (0 = no limit), or
  // on_block returns false. on_block is called after every block (at least every few hundred ms).
  // Returns true when the family is complete (all candidates decided).
  bool run(int threads, std::size_t max_codes,
           const std::function<bool(const LexicodeProgress&, const LexicodeState&)>& on_block);

  const LexicodeState& state() const { return state_; }
  const LexicodeParams& params() const { return params_; }
  bool complete() const { return state_.next_index >= total_; }

 private:
  LexicodeParams params_;
  LexicodeState state_;
  int d_, complexity_;
  Code mask_, v0_;
  unsigned __int128 total_;
  std::vector<Code> words_;  // all four rotations of every accepted code
  PrefixBuckets index_;      // words_ bucketed for the phase-1 test
  std::size_t index_words_ = 0;
};

// Convenience: the whole family, single call (used by tests and small runs).
std::vector<Code> generate_lexicode(const LexicodeParams& params, int threads = 1);

}  // namespace tagbench
