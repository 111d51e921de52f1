#include "codes/hamming_scan.hpp"

#include <algorithm>
#include <bit>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TAGBENCH_HAVE_AVX512_PATH 1
#endif

namespace tagbench {
namespace {

std::ptrdiff_t first_within_scalar(const Code* w, std::size_t n, Code v, int max_distance) {
  for (std::size_t i = 0; i < n; ++i)
    if (std::popcount(v ^ w[i]) <= max_distance) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

NearestWord nearest_scalar(const Code* w, std::size_t n, Code v, int max_distance) {
  NearestWord best;
  for (std::size_t i = 0; i < n; ++i) {
    const int d = std::popcount(v ^ w[i]);
    if (d <= max_distance && d < best.distance) {
      best.distance = d;
      best.index = static_cast<std::ptrdiff_t>(i);
    }
  }
  return best;
}

#ifdef TAGBENCH_HAVE_AVX512_PATH
// The scalar loops again with the POPCNT instruction (x86-64 since 2008; the baseline build targets
// the 2003 instruction set, where std::popcount is a library call of a dozen instructions).
__attribute__((target("popcnt"))) std::ptrdiff_t first_within_popcnt(const Code* w, std::size_t n, Code v,
                                                                     int max_distance) {
  for (std::size_t i = 0; i < n; ++i)
    if (__builtin_popcountll(v ^ w[i]) <= max_distance) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

__attribute__((target("popcnt"))) NearestWord nearest_popcnt(const Code* w, std::size_t n, Code v,
                                                             int max_distance) {
  NearestWord best;
  for (std::size_t i = 0; i < n; ++i) {
    const int d = __builtin_popcountll(v ^ w[i]);
    if (d <= max_distance && d < best.distance) {
      best.distance = d;
      best.index = static_cast<std::ptrdiff_t>(i);
    }
  }
  return best;
}

__attribute__((target("avx512f,avx512vpopcntdq"))) std::ptrdiff_t first_within_avx512(
    const Code* w, std::size_t n, Code v, int max_distance) {
  const __m512i vv = _mm512_set1_epi64(static_cast<long long>(v));
  const __m512i lim = _mm512_set1_epi64(max_distance + 1);  // popcount < lim
  std::size_t i = 0;
  // Four vectors per iteration: one branch per 32 words keeps the loop throughput-bound.
  for (; i + 32 <= n; i += 32) {
    const __m512i a = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_loadu_si512(w + i)));
    const __m512i b = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_loadu_si512(w + i + 8)));
    const __m512i c = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_loadu_si512(w + i + 16)));
    const __m512i d = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_loadu_si512(w + i + 24)));
    const __mmask8 ma = _mm512_cmplt_epu64_mask(a, lim), mb = _mm512_cmplt_epu64_mask(b, lim);
    const __mmask8 mc = _mm512_cmplt_epu64_mask(c, lim), md = _mm512_cmplt_epu64_mask(d, lim);
    if ((ma | mb | mc | md) != 0) {
      const std::uint32_t all = static_cast<std::uint32_t>(ma) | (static_cast<std::uint32_t>(mb) << 8) |
                                (static_cast<std::uint32_t>(mc) << 16) | (static_cast<std::uint32_t>(md) << 24);
      return static_cast<std::ptrdiff_t>(i + static_cast<std::size_t>(std::countr_zero(all)));
    }
  }
  for (; i + 8 <= n; i += 8) {
    const __m512i a = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_loadu_si512(w + i)));
    const __mmask8 m = _mm512_cmplt_epu64_mask(a, lim);
    if (m) return static_cast<std::ptrdiff_t>(i + static_cast<std::size_t>(std::countr_zero(static_cast<unsigned>(m))));
  }
  if (i < n) {
    const __mmask8 tail = static_cast<__mmask8>((1u << (n - i)) - 1);
    const __m512i a = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_maskz_loadu_epi64(tail, w + i)));
    const __mmask8 m = _mm512_mask_cmplt_epu64_mask(tail, a, lim);
    if (m) return static_cast<std::ptrdiff_t>(i + static_cast<std::size_t>(std::countr_zero(static_cast<unsigned>(m))));
  }
  return -1;
}

__attribute__((target("avx512f,avx512vpopcntdq"))) NearestWord nearest_avx512(const Code* w, std::size_t n,
                                                                              Code v, int max_distance) {
  NearestWord best;
  const __m512i vv = _mm512_set1_epi64(static_cast<long long>(v));
  __m512i lim = _mm512_set1_epi64(max_distance + 1);
  std::size_t i = 0;
  for (; i < n; i += 8) {
    const __mmask8 tail = n - i >= 8 ? static_cast<__mmask8>(0xFF) : static_cast<__mmask8>((1u << (n - i)) - 1);
    const __m512i a = _mm512_popcnt_epi64(_mm512_xor_si512(vv, _mm512_maskz_loadu_epi64(tail, w + i)));
    __mmask8 m = _mm512_mask_cmplt_epu64_mask(tail, a, lim);
    while (m) {  // rare: only words within the limit
      const int k = std::countr_zero(static_cast<unsigned>(m));
      m = static_cast<__mmask8>(m & (m - 1));
      const int d = std::popcount(v ^ w[i + static_cast<std::size_t>(k)]);
      if (d < best.distance) {
        best.distance = d;
        best.index = static_cast<std::ptrdiff_t>(i + static_cast<std::size_t>(k));
        lim = _mm512_set1_epi64(d);  // later words must be strictly nearer
      }
    }
  }
  return best;
}

bool cpu_has_avx512_popcnt() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vpopcntdq");
}
#endif

struct Impl {
  std::ptrdiff_t (*first)(const Code*, std::size_t, Code, int) = first_within_scalar;
  NearestWord (*nearest)(const Code*, std::size_t, Code, int) = nearest_scalar;
  const char* name = "scalar";
  bool popcnt = false;  // the POPCNT instruction (ChunkIndex's bucket scans)
  Impl() {
#ifdef TAGBENCH_HAVE_AVX512_PATH
    __builtin_cpu_init();
    if (__builtin_cpu_supports("popcnt")) {
      first = first_within_popcnt;
      nearest = nearest_popcnt;
      name = "popcnt";
      popcnt = true;
    }
    if (cpu_has_avx512_popcnt()) {
      first = first_within_avx512;
      nearest = nearest_avx512;
      name = "avx512-vpopcntdq";
    }
#endif
  }
};

const Impl& impl() {
  static const Impl chosen;
  return chosen;
}

}  // namespace

std::ptrdiff_t first_within(std::span<const Code> words, Code v, int max_distance) {
  if (max_distance < 0) return -1;
  return impl().first(words.data(), words.size(), v, max_distance);
}

NearestWord nearest_within(std::span<const Code> words, Code v, int max_distance) {
  if (max_distance < 0) return {};
  return impl().nearest(words.data(), words.size(), v, max_distance);
}

const char* hamming_scan_impl() { return impl().name; }

ChunkIndex::ChunkIndex(std::span<const Code> words, int bits, int chunks) {
  // Chunks of more than 20 bits would need a million buckets each: no index (chunks() 0).
  if (bits < 1 || bits > 64 || chunks < 1 || chunks > bits || (bits + chunks - 1) / chunks > 20) return;
  const auto c = static_cast<std::size_t>(chunks);
  lo_.resize(c);
  width_.resize(c);
  offsets_.resize(c);
  entries_.resize(c);
  for (std::size_t j = 0, at = 0; j < c; ++j) {  // widths differ by at most one bit
    const std::size_t wd = (static_cast<std::size_t>(bits) + j) / c;
    lo_[j] = static_cast<std::uint8_t>(at);
    width_[j] = static_cast<std::uint8_t>(wd);
    at += wd;
    const std::size_t nb = std::size_t{1} << wd;
    const Code mask = (Code{1} << wd) - 1;
    auto& off = offsets_[j];
    off.assign(nb + 1, 0);
    for (const Code w : words) ++off[((w >> lo_[j]) & mask) + 1];
    for (std::size_t b = 0; b < nb; ++b) off[b + 1] += off[b];
    std::vector<std::uint32_t> fill(off.begin(), off.end() - 1);
    entries_[j].resize(words.size());
    for (std::size_t i = 0; i < words.size(); ++i)  // ascending positions within each bucket
      entries_[j][fill[(words[i] >> lo_[j]) & mask]++] = static_cast<std::uint32_t>(i);
  }
}

namespace {
// One bucket's entries compared with v; best keeps the lowest position among the nearest.
inline void scan_bucket(const Code* words, const std::uint32_t* e, const std::uint32_t* end, Code v, int max_distance,
                        NearestWord& best) {
  for (; e != end; ++e) {
    const int d = std::popcount(v ^ words[*e]);
    if (d <= max_distance && (d < best.distance || (d == best.distance && *e < best.index))) {
      best.distance = d;
      best.index = static_cast<std::ptrdiff_t>(*e);
    }
  }
}
#ifdef TAGBENCH_HAVE_AVX512_PATH
__attribute__((target("popcnt"))) void scan_bucket_popcnt(const Code* words, const std::uint32_t* e,
                                                          const std::uint32_t* end, Code v, int max_distance,
                                                          NearestWord& best) {
  for (; e != end; ++e) {
    const int d = __builtin_popcountll(v ^ words[*e]);
    if (d <= max_distance && (d < best.distance || (d == best.distance && *e < best.index))) {
      best.distance = d;
      best.index = static_cast<std::ptrdiff_t>(*e);
    }
  }
}
#endif
}  // namespace

NearestWord ChunkIndex::nearest_within(std::span<const Code> words, Code v, int max_distance) const {
  NearestWord best;
  if (max_distance < 0) return best;
  if (max_distance >= chunks()) return tagbench::nearest_within(words, v, max_distance);  // no guarantee: all words
  for (std::size_t j = 0; j < lo_.size(); ++j) {
    const Code key = (v >> lo_[j]) & ((Code{1} << width_[j]) - 1);
    const std::uint32_t* e = entries_[j].data();
    const std::uint32_t *first = e + offsets_[j][key], *last = e + offsets_[j][key + 1];
#ifdef TAGBENCH_HAVE_AVX512_PATH
    if (impl().popcnt) {
      scan_bucket_popcnt(words.data(), first, last, v, max_distance, best);
      continue;
    }
#endif
    scan_bucket(words.data(), first, last, v, max_distance, best);
  }
  return best;
}

PrefixBuckets::PrefixBuckets(std::span<const Code> words, int bits, std::size_t target) {
  while (t_ < 14 && t_ < bits && (words.size() >> (t_ + 1)) >= target) ++t_;
  shift_ = bits - t_;
  const std::size_t nb = std::size_t{1} << t_;
  const auto bucket = [&](Code w) { return t_ ? static_cast<std::size_t>(w >> shift_) : std::size_t{0}; };
  offsets_.assign(nb + 1, 0);
  for (const Code w : words) ++offsets_[bucket(w) + 1];
  for (std::size_t i = 0; i < nb; ++i) offsets_[i + 1] += offsets_[i];
  sorted_.resize(words.size());
  std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (const Code w : words) sorted_[fill[bucket(w)]++] = w;
  masks_.resize(nb);
  for (std::size_t i = 0; i < nb; ++i) masks_[i] = static_cast<std::uint32_t>(i);
  std::stable_sort(masks_.begin(), masks_.end(),
                   [](std::uint32_t a, std::uint32_t b) { return std::popcount(a) < std::popcount(b); });
  mask_pop_.resize(nb);
  for (std::size_t i = 0; i < nb; ++i) mask_pop_[i] = static_cast<std::uint8_t>(std::popcount(masks_[i]));
}

std::optional<Code> PrefixBuckets::first_word_within(Code v, int max_distance) const {
  if (max_distance < 0) return std::nullopt;
  const auto q = t_ ? static_cast<std::uint32_t>(v >> shift_) : std::uint32_t{0};  // t_ = 0: one bucket
  const auto first = impl().first;
  for (std::size_t i = 0; i < masks_.size(); ++i) {
    if (mask_pop_[i] > max_distance) return std::nullopt;  // the prefixes alone differ too much from here on
    const std::uint32_t b = q ^ masks_[i];
    const std::uint32_t lo = offsets_[b], hi = offsets_[b + 1];
    if (lo == hi) continue;
    const std::ptrdiff_t k = first(sorted_.data() + lo, hi - lo, v, max_distance);
    if (k >= 0) return sorted_[lo + static_cast<std::size_t>(k)];
  }
  return std::nullopt;
}

}  // namespace tagbench
