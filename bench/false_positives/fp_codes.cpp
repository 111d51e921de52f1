#include "fp_codes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "code_experiments.hpp"
#include "codes/families.hpp"
#include "codes/lexicode.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

std::vector<ScoredFamily> complexity_families(int bits, int min_hamming, int lo, int hi, int threads) {
  if (lo < 0 || hi < lo) throw std::invalid_argument("complexity range " + std::to_string(lo) + ".." +
                                                     std::to_string(hi) + " is empty");
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<ScoredFamily> out;
  for (int c = lo; c <= hi; ++c) {
    LexicodeParams p;
    p.bits = bits;
    p.min_hamming = min_hamming;
    p.min_complexity = c;
    p.validate();
    const auto t0 = std::chrono::steady_clock::now();
    auto codes = generate_lexicode(p, threads);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    FamilyInfo info;
    info.bits = bits;
    info.min_hamming = min_hamming;
    info.min_complexity = c;
    info.seed = p.resolved_seed();
    info.order = to_string(p.order);
    info.generator = "tagbench-lexicode " + std::to_string(kGeneratorVersion);
    info.name = std::to_string(bits) + "h" + std::to_string(min_hamming) + "c" + std::to_string(c);
    std::string scheme = std::to_string(bits) + "h" + std::to_string(min_hamming) + ", complexity >= " + std::to_string(c);
    out.push_back({std::move(scheme), TagFamily(std::move(info), std::move(codes)), secs});
  }
  return out;
}

std::vector<ScoredFamily> fig7_schemes() {
  const std::vector<std::pair<std::string, std::string>> names{
      {"ARToolkit+ (simple)", "artoolkitplus-simple"}, {"ARToolkit+ (BCH)", "artoolkitplus-bch"},
      {"ARTag", "artag-2046"}, {"36h10", "36h10"}, {"36h15", "36h15"}, {"36h11", "36h11"}};
  std::vector<ScoredFamily> out;
  for (const auto& [scheme, name] : names) out.push_back({scheme, builtin_family(name), 0});
  return out;
}

double random_payload_rate(std::size_t codes, int bits, int k) {
  const double words = 4.0 * static_cast<double>(codes) * hamming_ball_volume(bits, k);
  return std::min(1.0, words / std::ldexp(1.0, bits));
}

std::vector<CodeCurveRow> code_curves(const corpus::CandidateStore& store, const std::vector<ScoredFamily>& families,
                                      int max_k, int jobs) {
  if (max_k < 0) throw std::invalid_argument("bits corrected must be >= 0");
  // The records of each subset; "all" is the store itself.
  const std::vector<std::string> kinds{"still", "video-frame"};
  std::vector<std::vector<corpus::CandidateRecord>> by_kind(kinds.size());
  for (const auto& r : store.records) {
    if (r.image >= store.images.size())
      throw std::invalid_argument("candidate store: record of image " + std::to_string(r.image) +
                                  " but the index lists " + std::to_string(store.images.size()) + " images");
    const auto& kind = store.images[r.image].kind;
    for (std::size_t i = 0; i < kinds.size(); ++i)
      if (kind == kinds[i]) by_kind[i].push_back(r);
  }
  std::vector<CodeCurveRow> rows;
  for (const auto& sf : families) {
    const TagFamily& f = sf.family;
    const int K = std::min(max_k, f.bits());
    for (std::size_t s = 0; s <= kinds.size(); ++s) {
      const auto& records = s == 0 ? store.records : by_kind[s - 1];
      const auto score = corpus::score_family(records, f, K, jobs);
      for (int k = 0; k <= K; ++k) {
        CodeCurveRow r;
        r.scheme = sf.scheme;
        r.family = f.name();
        r.bits = f.bits();
        r.min_hamming = f.min_hamming();
        r.min_complexity = f.info().min_complexity;
        r.codes = f.size();
        r.subset = s == 0 ? "all" : kinds[s - 1];
        r.bits_corrected = k;
        r.quads = score.quads;
        r.accepted = score.accepted[static_cast<std::size_t>(k)];
        r.rate = r.quads ? static_cast<double>(r.accepted) / static_cast<double>(r.quads) : 0.0;
        r.ci = wilson_interval(r.accepted, r.quads);
        r.theory_rate = random_payload_rate(f.size(), f.bits(), k);
        r.theory_exact = 2 * k < f.min_hamming();
        r.generation_seconds = sf.generation_seconds;
        rows.push_back(std::move(r));
      }
    }
  }
  return rows;
}

std::string code_curves_csv(const std::vector<CodeCurveRow>& rows) {
  std::ostringstream o;
  o.precision(6);
  o << "scheme,family,bits,min_hamming,min_complexity,codes,subset,bits_corrected,quads,accepted,rate,ci95_lo,ci95_hi,"
       "theory_rate,theory_exact,generation_seconds\n";
  for (const auto& r : rows)
    o << csv_field(r.scheme) << ',' << r.family << ',' << r.bits << ',' << r.min_hamming << ',' << r.min_complexity
      << ',' << r.codes << ',' << r.subset << ',' << r.bits_corrected << ',' << r.quads << ',' << r.accepted << ','
      << r.rate << ',' << r.ci.lo << ',' << r.ci.hi << ',' << r.theory_rate << ',' << (r.theory_exact ? 1 : 0) << ','
      << r.generation_seconds << '\n';
  return o.str();
}

}  // namespace tagbench::bench
