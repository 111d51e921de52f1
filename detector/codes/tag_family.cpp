#include "codes/tag_family.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "codes/complexity.hpp"
#include "codes/hamming_scan.hpp"

namespace tagbench {

namespace {
int width_of(int bits) {
  for (int d = 1; d <= kMaxPayloadWidth; ++d)
    if (d * d == bits) return d;
  return -1;
}
}  // namespace

TagFamily::TagFamily(FamilyInfo info, std::vector<Code> codes, bool check_distance)
    : info_(std::move(info)), codes_(std::move(codes)) {
  const std::string who = "family '" + info_.name + "': ";
  if (info_.bits > 64) throw std::invalid_argument(who + "bits " + std::to_string(info_.bits) + " is over 64");
  d_ = width_of(info_.bits);
  if (d_ < 2) throw std::invalid_argument(who + "bits " + std::to_string(info_.bits) + " is not a square payload");
  if (info_.name.empty()) throw std::invalid_argument("family: the name is empty");
  for (const char ch : info_.name)  // a name is printed in headers, CSV cells and one-line messages
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
      throw std::invalid_argument("family: the name holds a control character (a line break)");
  if (info_.min_hamming < 1 || info_.min_hamming > info_.bits)
    throw std::invalid_argument(who + "hamming " + std::to_string(info_.min_hamming) + " is outside 1..bits (" +
                                std::to_string(info_.bits) + ")");
  if (info_.min_complexity < 0 || info_.min_complexity > info_.bits)
    throw std::invalid_argument(who + "complexity " + std::to_string(info_.min_complexity) + " is outside 0..bits (" +
                                std::to_string(info_.bits) + ")");
  if (codes_.empty()) throw std::invalid_argument(who + "has no codes");
  const Code mask = low_mask(info_.bits);
  words_.reserve(codes_.size() * 4);
  exact_.reserve(codes_.size() * 4);
  for (std::size_t id = 0; id < codes_.size(); ++id) {
    if (codes_[id] & ~mask)
      throw std::invalid_argument(who + "code " + std::to_string(id) + " " + hex_code(codes_[id]) + " has more than " +
                                  std::to_string(info_.bits) + " bits");
    Code r = codes_[id];
    for (int k = 0; k < 4; ++k, r = rotate90(r, d_)) {
      words_.push_back(r);
      exact_.emplace(r, static_cast<std::uint32_t>(4 * id + k));  // keeps the first (lowest id, rotation)
    }
  }
  buckets_ = PrefixBuckets(words_, info_.bits);
  if (words_.size() >= 256) {
    chunked_.resize(9);
    // Chunks under 6 bits leave too many words per bucket: for 36h11 (2348 words) a search within 3
    // bits took 0.06 us with 9-bit chunks, 0.19 us with 6-bit ones, 0.33 us with 5 (as the scan of
    // every word) and 0.55 us with 4 (a micro-benchmark, 100,000 words 9 bit flips from a code).
    for (int c = 3; c <= 8 && info_.bits / c >= 6; ++c)
      chunked_[static_cast<std::size_t>(c)] = ChunkIndex(words_, info_.bits, c);
  }
  {
    std::vector<Code> sorted = codes_;
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end()) throw std::invalid_argument(who + "duplicate code " + hex_code(*dup));
  }
  if (check_distance) {
    for (std::size_t id = 0; id < codes_.size(); ++id) {
      const Code c = codes_[id];
      if (self_rotation_distance(c, d_) < info_.min_hamming)
        throw std::invalid_argument(who + "code " + std::to_string(id) + " " + hex_code(c) +
                                    " is closer than h=" + std::to_string(info_.min_hamming) + " to its own rotation");
      // Codes before id, all rotations: each unordered pair once.
      const auto hit = first_within(std::span<const Code>(words_.data(), 4 * id), c, info_.min_hamming - 1);
      if (hit >= 0)
        throw std::invalid_argument(who + "codes " + std::to_string(hit / 4) + " and " + std::to_string(id) +
                                    " are closer than h=" + std::to_string(info_.min_hamming));
    }
  }
}

namespace {
// The index for a search within m bits (c = max(3, m + 1) chunks), if the family has one.
const ChunkIndex* chunk_index_for(const std::vector<ChunkIndex>& chunked, int m) {
  if (m < 0 || m >= 8) return nullptr;  // no index beyond 8 chunks (and no m + 1 overflow)
  const auto c = static_cast<std::size_t>(std::max(3, m + 1));
  return c < chunked.size() && chunked[c].chunks() > 0 ? &chunked[c] : nullptr;
}
}  // namespace

NearestWord TagFamily::nearest_word(Code observed, int max_distance) const {
  observed &= low_mask(info_.bits);
  if (const ChunkIndex* ix = chunk_index_for(chunked_, max_distance)) return ix->nearest_within(words_, observed, max_distance);
  return nearest_within(words_, observed, max_distance);
}

std::optional<DecodeResult> TagFamily::decode(Code observed, int max_corrected) const {
  observed &= low_mask(info_.bits);
  if (const auto it = exact_.find(observed); it != exact_.end())
    return DecodeResult{static_cast<int>(it->second / 4), 0, static_cast<int>(it->second % 4)};
  if (max_corrected <= 0) return std::nullopt;
  if (const ChunkIndex* ix = chunk_index_for(chunked_, max_corrected)) {
    const NearestWord n = ix->nearest_within(words_, observed, max_corrected);
    if (n.index < 0) return std::nullopt;
    return DecodeResult{static_cast<int>(n.index / 4), n.distance, static_cast<int>(n.index % 4)};
  }
  // With max_corrected <= (h-1)/2 at most one word is within reach, so the first hit is the answer.
  if (2 * max_corrected < info_.min_hamming) {
    const auto w = buckets_.first_word_within(observed, max_corrected);
    if (!w) return std::nullopt;
    const std::uint32_t e = exact_.at(*w);
    return DecodeResult{static_cast<int>(e / 4), hamming(observed, *w), static_cast<int>(e % 4)};
  }
  const NearestWord n = nearest_within(words_, observed, max_corrected);
  if (n.index < 0) return std::nullopt;
  return DecodeResult{static_cast<int>(n.index / 4), n.distance, static_cast<int>(n.index % 4)};
}

DistanceStats distance_stats(std::span<const Code> codes, int d, int threads) {
  const int bits = d * d;
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n = codes.size();
  std::vector<Code> rot(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    Code r = codes[i];
    for (int k = 0; k < 4; ++k, r = rotate90(r, d)) rot[4 * i + static_cast<std::size_t>(k)] = r;
  }
  struct Partial {
    std::vector<std::uint64_t> hist;
    int min_plain = 65;
  };
  std::vector<Partial> parts(static_cast<std::size_t>(threads));
  std::atomic<std::size_t> next{0};
  auto work = [&](Partial& p) {
    p.hist.assign(static_cast<std::size_t>(bits) + 1, 0);
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      for (std::size_t j = i + 1; j < n; ++j) {
        const Code* r = &rot[4 * j];
        const int plain = hamming(codes[i], r[0]);
        const int m = std::min({plain, hamming(codes[i], r[1]), hamming(codes[i], r[2]), hamming(codes[i], r[3])});
        p.min_plain = std::min(p.min_plain, plain);
        ++p.hist[static_cast<std::size_t>(m)];
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work, std::ref(parts[static_cast<std::size_t>(t)]));
    work(parts[0]);
  }
  DistanceStats s;
  s.histogram.assign(static_cast<std::size_t>(bits) + 1, 0);
  s.min_plain = 65;
  for (const auto& p : parts) {
    s.min_plain = std::min(s.min_plain, p.min_plain);
    for (std::size_t k = 0; k < p.hist.size(); ++k) s.histogram[k] += p.hist[k];
  }
  s.min_self_rotation = 65;
  for (const Code c : codes) s.min_self_rotation = std::min(s.min_self_rotation, self_rotation_distance(c, d));
  int min_pair = 65;
  for (std::size_t k = 0; k < s.histogram.size(); ++k)
    if (s.histogram[k]) { min_pair = static_cast<int>(k); break; }
  s.min_with_rotations = std::min(min_pair, s.min_self_rotation);
  if (n < 2) {  // no pairs: only the self-rotation bound applies
    s.min_plain = bits;
    s.min_with_rotations = std::min(s.min_self_rotation, bits);
  }
  return s;
}

int min_complexity_of(std::span<const Code> codes, int d) {
  int m = 1 << 30;
  for (const Code c : codes) m = std::min(m, rectangle_complexity(c, d));
  return codes.empty() ? 0 : m;
}

}  // namespace tagbench
