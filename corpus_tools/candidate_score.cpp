// Scoring a family against stored candidate payloads (the paper's Figs. 6 and 7 from the store).
#include <algorithm>
#include <stdexcept>
#include <thread>
#include <vector>

#include "candidates.hpp"

namespace tagbench::corpus {

FamilyScore score_family(const std::vector<CandidateRecord>& records, const TagFamily& family, int max_k, int jobs) {
  if (max_k < 0 || max_k > family.bits()) throw std::invalid_argument("max bits corrected out of range");
  const int d = family.payload_width();
  const std::size_t K = static_cast<std::size_t>(max_k);
  if (jobs <= 0) jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n = records.size();
  const std::size_t chunk = 1 << 14;
  std::vector<std::vector<std::uint64_t>> hist(static_cast<std::size_t>(jobs), std::vector<std::uint64_t>(K + 2, 0));
  std::atomic<std::size_t> next{0};
  auto work = [&](std::vector<std::uint64_t>& h) {
    for (;;) {
      const std::size_t b = next.fetch_add(chunk);
      if (b >= n) return;
      const std::size_t e = std::min(n, b + chunk);
      for (std::size_t i = b; i < e; ++i) {
        const auto& r = records[i];
        if (r.d != d) continue;
        ++h[K + 1];  // records of this width
        // decode with max_k returns the nearest code's distance (the only one in reach when
        // max_k <= (h-1)/2), so decode(bits, k) accepts exactly when that distance is <= k.
        if (const auto dec = family.decode(r.bits, max_k)) ++h[static_cast<std::size_t>(dec->hamming)];
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < jobs; ++t) pool.emplace_back(work, std::ref(hist[static_cast<std::size_t>(t)]));
  work(hist[0]);
  for (auto& t : pool) t.join();
  FamilyScore s;
  s.accepted.assign(K + 1, 0);
  for (const auto& h : hist) {
    s.quads += h[K + 1];
    for (std::size_t k = 0; k <= K; ++k) s.accepted[k] += h[k];
  }
  for (std::size_t k = 1; k <= K; ++k) s.accepted[k] += s.accepted[k - 1];
  return s;
}

}  // namespace tagbench::corpus
