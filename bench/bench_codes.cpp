// Speed of the coding system: decoding a word against a family (all ids and rotations) and the
// lexicode generator's candidate test. `make bench` records the output in results/.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>
#include <string>

#include "codes/families.hpp"
#include "codes/hamming_scan.hpp"
#include "codes/lexicode.hpp"

namespace {

using tagbench::Code;

// The family, or nullptr (and the benchmark marked skipped) while its generator run is unfinished.
const tagbench::TagFamily* family_or_skip(benchmark::State& state, const char* name) {
  const auto names = tagbench::builtin_family_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    state.SkipWithError((std::string("family ") + name + " is still being generated").c_str());
    return nullptr;
  }
  return &tagbench::builtin_family(name);
}

// Random 36-bit words: the case of a false quad (no code within reach, so the whole table is scanned).
void BM_DecodeRandomWord(benchmark::State& state, const char* family, int max_corrected) {
  const auto* fp = family_or_skip(state, family);
  if (!fp) return;
  const auto& f = *fp;
  std::mt19937_64 rng(42);
  std::vector<Code> words(4096);
  for (auto& w : words) w = rng() & tagbench::low_mask(f.bits());
  std::size_t i = 0, hits = 0;
  for (auto _ : state) {
    const auto r = f.decode(words[i++ & 4095], max_corrected);
    hits += r.has_value();
    benchmark::DoNotOptimize(r);
  }
  state.counters["codes"] = static_cast<double>(f.size());
  state.counters["hits"] = static_cast<double>(hits);
  state.SetLabel(tagbench::hamming_scan_impl());
}

// A true tag with 2 flipped bits: the usual case of a real detection.
void BM_DecodeTrueTag(benchmark::State& state, const char* family, int max_corrected) {
  const auto* fp = family_or_skip(state, family);
  if (!fp) return;
  const auto& f = *fp;
  std::mt19937_64 rng(7);
  std::vector<Code> words(4096);
  for (auto& w : words) {
    const Code c = f.codes()[rng() % f.size()];
    w = tagbench::rotate(c, f.payload_width(), static_cast<int>(rng() % 4)) ^ (Code{1} << (rng() % 36)) ^
        (Code{1} << (rng() % 36));
  }
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(f.decode(words[i++ & 4095], max_corrected));
  state.SetLabel(tagbench::hamming_scan_impl());
}

BENCHMARK_CAPTURE(BM_DecodeRandomWord, 36h10_k2, "36h10", 2);
BENCHMARK_CAPTURE(BM_DecodeRandomWord, 36h11_k2, "36h11", 2);
BENCHMARK_CAPTURE(BM_DecodeRandomWord, 36h10_k4, "36h10", 4);
BENCHMARK_CAPTURE(BM_DecodeRandomWord, 36h10_k0, "36h10", 0);
BENCHMARK_CAPTURE(BM_DecodeTrueTag, 36h10_k2, "36h10", 2);

// The generator's phase-1 test (PrefixBuckets, as lexicode.cpp uses it) on a finished family's code set:
// candidates per second per thread at the end of a run, the slowest phase, where nearly every
// candidate is rejected by some code.
void BM_GeneratorCandidateTest(benchmark::State& state, const char* family) {
  const auto* fp = family_or_skip(state, family);
  if (!fp) return;
  const tagbench::PrefixBuckets index(fp->rotated_words(), fp->bits());
  Code v = 0x123456789;
  std::size_t rejected = 0;
  for (auto _ : state) {
    v = (v + tagbench::kLexicodePrime) & tagbench::low_mask(fp->bits());
    rejected += index.any_within(v, fp->min_hamming() - 1);
  }
  benchmark::DoNotOptimize(rejected);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["rejected_fraction"] = static_cast<double>(rejected) / static_cast<double>(state.iterations());
  state.SetLabel(tagbench::hamming_scan_impl());
}
BENCHMARK_CAPTURE(BM_GeneratorCandidateTest, 36h11, "36h11");
BENCHMARK_CAPTURE(BM_GeneratorCandidateTest, 36h10, "36h10");


}  // namespace

BENCHMARK_MAIN();
