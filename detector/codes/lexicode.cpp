#include "codes/lexicode.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "codes/complexity.hpp"
#include "codes/hamming_scan.hpp"
#include "codes/java_random.hpp"

namespace tagbench {

const char* to_string(CandidateOrder o) { return o == CandidateOrder::kPrime ? "prime" : "lex"; }

CandidateOrder parse_candidate_order(const std::string& s) {
  if (s == "prime") return CandidateOrder::kPrime;
  if (s == "lex") return CandidateOrder::kLex;
  throw std::invalid_argument("unknown candidate order '" + s + "' (expected prime or lex)");
}

int LexicodeParams::payload_width() const {
  for (int d = 1; d <= kMaxPayloadWidth; ++d)
    if (d * d == bits) return d;
  return -1;
}

int LexicodeParams::resolved_complexity() const {
  return min_complexity >= 0 ? min_complexity : std::min(10, bits / 3);
}

std::int64_t LexicodeParams::resolved_seed() const {
  return seed ? *seed : std::int64_t{bits} * 10000 + min_hamming * 100 + resolved_complexity();
}

void LexicodeParams::validate() const {
  const int d = payload_width();
  if (bits > 64) throw std::invalid_argument("bits " + std::to_string(bits) + " is over 64");
  if (d < 3 || d > kMaxPayloadWidth)
    throw std::invalid_argument("bits " + std::to_string(bits) + " is not the square of a payload width 3.." +
                                std::to_string(kMaxPayloadWidth));
  if (min_hamming < 1 || min_hamming > bits)
    throw std::invalid_argument("hamming " + std::to_string(min_hamming) + " is outside 1.." + std::to_string(bits));
  if (min_complexity < -1 || min_complexity > bits)
    throw std::invalid_argument("complexity " + std::to_string(min_complexity) + " is outside 0.." + std::to_string(bits));
}

LexicodeGenerator::LexicodeGenerator(LexicodeParams params, LexicodeState start)
    : params_(params), state_(std::move(start)) {
  params_.validate();
  d_ = params_.payload_width();
  complexity_ = params_.resolved_complexity();
  mask_ = low_mask(params_.bits);
  v0_ = static_cast<Code>(JavaRandom(params_.resolved_seed()).next_long());
  total_ = static_cast<unsigned __int128>(1) << params_.bits;
  if (state_.next_index > total_) throw std::invalid_argument("checkpoint index is past the end of the run");
  for (const Code c : state_.codes) {
    Code r = c;
    for (int i = 0; i < 4; ++i, r = rotate90(r, d_)) words_.push_back(r);
  }
}

Code LexicodeGenerator::candidate(unsigned __int128 k) const {
  if (params_.order == CandidateOrder::kLex) return static_cast<Code>(k) & mask_;
  // The original adds p before testing, so candidate 0 is V0 + p.
  return (v0_ + static_cast<Code>(k + 1) * kLexicodePrime) & mask_;
}

namespace {

struct Survivor {
  unsigned __int128 index;
  Code value;
};

}  // namespace

bool LexicodeGenerator::run(int threads, std::size_t max_codes,
                            const std::function<bool(const LexicodeProgress&, const LexicodeState&)>& on_block) {
  using Clock = std::chrono::steady_clock;
  threads = std::max(1, threads);
  const int h = params_.min_hamming;
  const auto t_start = Clock::now();
  const double elapsed_before = state_.elapsed_seconds;
  const unsigned __int128 index_before = state_.next_index;
  std::uint64_t block = 4096;  // adapted below; never changes the result
  constexpr std::uint64_t kChunk = 2048;

  while (state_.next_index < total_ && (max_codes == 0 || state_.codes.size() < max_codes)) {
    const unsigned __int128 left = total_ - state_.next_index;
    const std::uint64_t n = left < block ? static_cast<std::uint64_t>(left) : block;
    const unsigned __int128 base = state_.next_index;

    // Phase 1 (parallel): distance to codes accepted before the block, and the self-rotation rule.
    if (index_words_ != words_.size()) {  // re-bucket only when codes were added
      index_ = PrefixBuckets(words_, params_.bits);
      index_words_ = words_.size();
    }
    const std::uint64_t nchunks = (n + kChunk - 1) / kChunk;
    std::vector<std::vector<Survivor>> found(nchunks);
    std::atomic<std::uint64_t> next_chunk{0};
    auto worker = [&] {
      for (;;) {
        const std::uint64_t ci = next_chunk.fetch_add(1, std::memory_order_relaxed);
        if (ci >= nchunks) return;
        const std::uint64_t lo = ci * kChunk, hi = std::min(n, lo + kChunk);
        for (std::uint64_t i = lo; i < hi; ++i) {
          const Code v = candidate(base + i);
          if (index_.any_within(v, h - 1)) continue;
          if (self_rotation_distance(v, d_) < h) continue;
          found[ci].push_back({base + i, v});
        }
      }
    };
    const int use_threads = n >= 4 * kChunk ? threads : 1;
    {
      std::vector<std::jthread> pool;
      for (int t = 1; t < use_threads; ++t) pool.emplace_back(worker);
      worker();
    }

    // Phase 2 (in order): codes accepted earlier in this block, then complexity (costly, so last).
    const std::size_t words_before = words_.size();
    std::size_t survivors = 0;
    bool stopped_early = false;
    for (const auto& chunk : found) {
      for (const Survivor& s : chunk) {
        ++survivors;
        const std::span<const Code> in_block(words_.data() + words_before, words_.size() - words_before);
        if (first_within(in_block, s.value, h - 1) >= 0) continue;
        if (!complexity_at_least(s.value, d_, complexity_)) continue;
        state_.codes.push_back(s.value);
        Code r = s.value;
        for (int i = 0; i < 4; ++i, r = rotate90(r, d_)) words_.push_back(r);
        if (max_codes != 0 && state_.codes.size() >= max_codes) {
          state_.next_index = s.index + 1;  // the prefix is exact: later candidates are undecided
          stopped_early = true;
          break;
        }
      }
      if (stopped_early) break;
    }
    if (!stopped_early) state_.next_index = base + n;

    // Keep phase 2 small and the blocks long enough to amortise the threads.
    if (survivors < 256 && block < (std::uint64_t{1} << 22)) block *= 2;
    else if (survivors > 4096 && block > 1024) block /= 2;

    const double run_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    state_.elapsed_seconds = elapsed_before + run_seconds;
    LexicodeProgress p;
    p.done = state_.next_index;
    p.total = total_;
    p.codes = state_.codes.size();
    p.elapsed_seconds = state_.elapsed_seconds;
    p.candidates_per_second = run_seconds > 0 ? static_cast<double>(state_.next_index - index_before) / run_seconds : 0;
    if (on_block && !on_block(p, state_)) break;
  }
  return complete();
}

std::vector<Code> generate_lexicode(const LexicodeParams& params, int threads) {
  LexicodeGenerator g(params);
  g.run(threads, 0, nullptr);
  return g.state().codes;
}

}  // namespace tagbench
