#include "detect/boundaries.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tagbench {
namespace {

constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

std::size_t slot_of(std::uint64_t key, std::size_t mask) {
  key ^= key >> 33;  // a 64-bit mix (splitmix64's finaliser) so neighbouring ids spread out
  key *= 0xff51afd7ed558ccdULL;
  key ^= key >> 33;
  return static_cast<std::size_t>(key) & mask;
}

class PairTable {
 public:
  // Sized for the image (a slot per 64 pixels, at least 64; it grows when half full): emptying a
  // frame-sized table for each small crop of the second look cost more than the crop's own pass.
  // Group indices follow the order pairs are first met, whatever the size.
  PairTable(BoundaryScratch& s, std::size_t pixels) : s_(s) {
    s_.keys.assign(std::max<std::size_t>(64, std::bit_ceil(pixels / 64)), kEmpty);
    s_.values.resize(s_.keys.size());
  }
  // The group index of the pair `key`, a new one (== groups so far) when first met.
  std::uint32_t get(std::uint64_t key) {
    std::size_t mask = s_.keys.size() - 1, i = slot_of(key, mask);
    while (s_.keys[i] != kEmpty) {
      if (s_.keys[i] == key) return s_.values[i];
      i = (i + 1) & mask;
    }
    const std::uint32_t g = n_++;
    s_.keys[i] = key;
    s_.values[i] = g;
    if (2 * static_cast<std::size_t>(n_) > s_.keys.size()) grow();
    return g;
  }
  std::uint32_t size() const { return n_; }

 private:
  void grow() {
    std::vector<std::uint64_t> keys(s_.keys.size() * 2, kEmpty);
    std::vector<std::uint32_t> values(keys.size());
    const std::size_t mask = keys.size() - 1;
    for (std::size_t j = 0; j < s_.keys.size(); ++j) {
      if (s_.keys[j] == kEmpty) continue;
      std::size_t i = slot_of(s_.keys[j], mask);
      while (keys[i] != kEmpty) i = (i + 1) & mask;
      keys[i] = s_.keys[j];
      values[i] = s_.values[j];
    }
    s_.keys.swap(keys);
    s_.values.swap(values);
  }
  BoundaryScratch& s_;
  std::uint32_t n_ = 0;
};

// The labels of one row of a Components (its runs, with one label per run), read left to right.
class RowLabels {
 public:
  RowLabels(const Components& c, const std::vector<std::uint32_t>& labels, int y)
      : runs_(c.runs.data()), labels_(labels.data()), i_(c.row_start[static_cast<std::size_t>(y)]) {}
  // Moves to the run holding column x (never left: x is at least every column sought before).
  void seek(int x) {
    while (runs_[i_].x1 < x) ++i_;
  }
  // The label of column x, at or right of the last one sought (at most a run or two further on).
  std::uint32_t at(int x) const {
    std::uint32_t j = i_;
    while (runs_[j].x1 < x) ++j;
    return labels_[j];
  }

 private:
  const ClassRun* runs_;
  const std::uint32_t* labels_;
  std::uint32_t i_;
};

}  // namespace

void group_boundaries(const TernaryImage& img, const Components& comp, const BoundaryOptions& opt,
                      BoundaryScratch& s, BoundaryGroups& out) {
  const int w = img.width, h = img.height;
  s.raw.clear();
  s.raw_group.clear();
  PairTable table(s, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  // Each run's label when its component is big enough, else none: one look at the sizes per run
  // instead of two or more per boundary pixel (the sizes are read out of order).
  const std::uint32_t min_size = opt.min_component_pixels;
  s.big_label.resize(comp.run_label.size());
  for (std::size_t i = 0; i < comp.run_label.size(); ++i) {
    const std::uint32_t id = comp.run_label[i];
    s.big_label[i] = id != kNoComponent && comp.size[id] >= min_size ? id : kNoComponent;
  }
  std::uint64_t last_key = kEmpty;
  std::uint32_t last_group = 0;
  auto big = [](std::uint32_t id) { return id != kNoComponent; };

  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const std::uint8_t* v = img.data.data() + row;
    const std::uint8_t* below = y + 1 < h ? v + w : nullptr;
    // Labels from the runs (components.hpp): a cursor per row, at the run holding the lowest column
    // asked for so far; the pixels are visited left to right, so each only moves right.
    RowLabels here(comp, s.big_label, y), next(comp, s.big_label, below ? y + 1 : y);
    int diagonal_x = -2;  // the last pixel of this row that added the point toward (x - 1, y + 1)'s partner
    // One pixel: its points toward the right, below and the two diagonals below.
    auto pixel = [&](int x) __attribute__((always_inline)) {
      const std::uint8_t v0 = v[x];
      const bool right = x + 1 < w;
      // Fast exit: nothing of the opposite class among the four forward neighbours.
      const bool any = (right && v0 + v[x + 1] == 255) ||
                       (below && (v0 + below[x] == 255 || (x > 0 && v0 + below[x - 1] == 255) ||
                                  (right && v0 + below[x + 1] == 255)));
      if (v0 == kTernaryUnknown || !any) return;
      here.seek(x);
      const std::uint32_t l0 = here.at(x);
      if (!big(l0)) return;
      if (below) next.seek(x > 0 ? x - 1 : 0);
      // Inlined (GCC and Clang keep it a call otherwise): four call sites per boundary pixel. The
      // neighbour's label is looked up only when its class is the opposite one.
      auto add = [&](int dx, int dy, std::uint8_t v1, RowLabels& labels) __attribute__((always_inline)) {
        if (v0 + v1 != 255) return false;
        const std::uint32_t l1 = labels.at(x + dx);
        if (!big(l1)) return false;
        const std::uint64_t key = l0 < l1 ? (std::uint64_t{l1} << 32 | l0) : (std::uint64_t{l0} << 32 | l1);
        const int sign = v1 > v0 ? 1 : -1;  // toward the light pixel
        s.raw.push_back(BoundaryPoint{2 * x + dx, 2 * y + dy, static_cast<std::int8_t>(sign * dx),
                                      static_cast<std::int8_t>(sign * dy)});
        // Consecutive points mostly belong to the same pair: a one-entry cache skips most lookups.
        if (key != last_key) {
          last_key = key;
          last_group = table.get(key);
        }
        s.raw_group.push_back(last_group);
        return true;
      };
      if (right) add(1, 0, v[x + 1], here);
      if (below) {
        add(0, 1, below[x], next);
        // (x-1, y)->(x, y+1) and (x, y)->(x-1, y+1) meet at the same point: add it once.
        if (x > 0 && diagonal_x != x - 1) add(-1, 1, below[x - 1], next);
        if (right && add(1, 1, below[x + 1], next)) diagonal_x = x;
      }
    };
    int x = 0;
#if defined(__SSE2__)
    // 16 pixels at a time: a pixel none of whose four forward neighbours is of the opposite class
    // (v0 + v1 == 255, which for bytes is their wrapping sum being 0xFF: the sum is at most 510)
    // adds nothing (most of a frame: flat, inside a region or next to unknown pixels); the others are
    // visited in order. The same points in the same order as one pixel at a time.
    if (below) {
      if (w > 0) pixel(x++);
      const __m128i ff = _mm_set1_epi8(static_cast<char>(0xFF));
      const auto opposite = [&](__m128i a, const std::uint8_t* q) {
        return _mm_cmpeq_epi8(_mm_add_epi8(a, _mm_loadu_si128(reinterpret_cast<const __m128i*>(q))), ff);
      };
      for (; x + 17 <= w; x += 16) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v + x));
        const __m128i any = _mm_or_si128(_mm_or_si128(opposite(a, v + x + 1), opposite(a, below + x - 1)),
                                         _mm_or_si128(opposite(a, below + x), opposite(a, below + x + 1)));
        unsigned todo = static_cast<unsigned>(_mm_movemask_epi8(any));
        while (todo) {
          pixel(x + std::countr_zero(todo));
          todo &= todo - 1;
        }
      }
    }
#endif
    for (; x < w; ++x) pixel(x);
  }

  // Counting sort of the points by group (stable: each group keeps scan order).
  const std::uint32_t ng = table.size();
  out.offsets.assign(static_cast<std::size_t>(ng) + 1, 0);
  for (const std::uint32_t g : s.raw_group) ++out.offsets[static_cast<std::size_t>(g) + 1];
  for (std::size_t g = 0; g < ng; ++g) out.offsets[g + 1] += out.offsets[g];
  s.fill.assign(out.offsets.begin(), out.offsets.end() - 1);
  out.points.resize(s.raw.size());
  for (std::size_t i = 0; i < s.raw.size(); ++i) out.points[s.fill[s.raw_group[i]]++] = s.raw[i];
  if (ng == 0) out.offsets.clear();
}

BoundaryGroups group_boundaries(const TernaryImage& img, const Components& comp, const BoundaryOptions& opt) {
  BoundaryScratch s;
  BoundaryGroups out;
  group_boundaries(img, comp, opt, s, out);
  return out;
}

}  // namespace tagbench
