#include "codes/complexity.hpp"

#include <array>
#include <bit>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tagbench {
namespace {

// The rectangles of a d x d grid as bit masks, in the painter's loop order.
struct RectTable {
  std::vector<Code> masks;
  explicit RectTable(int d) {
    for (int y0 = 0; y0 < d; ++y0)
      for (int y1 = y0; y1 < d; ++y1)
        for (int x0 = 0; x0 < d; ++x0)
          for (int x1 = x0; x1 < d; ++x1) {
            Code m = 0;
            for (int y = y0; y <= y1; ++y)
              for (int x = x0; x <= x1; ++x) m |= Code{1} << (y * d + x);
            masks.push_back(m);
          }
  }
};

const RectTable& rects_for(int d) {
  // Built once per width on first use; immutable afterwards (thread-safe static init).
  static const auto tables = []<std::size_t... D>(std::index_sequence<D...>) {
    return std::array<RectTable, sizeof...(D)>{RectTable(static_cast<int>(D))...};
  }(std::make_index_sequence<kMaxPayloadWidth + 1>());
  return tables[static_cast<std::size_t>(d)];
}

// Paints greedily; returns the number of rectangles, or stops early at `limit`.
int paint(Code target, int d, int limit) {
  if (d < 1 || d > kMaxPayloadWidth)
    throw std::invalid_argument("rectangle_complexity: payload width must be 1.." + std::to_string(kMaxPayloadWidth));
  const Code all = low_mask(d * d);
  const auto& masks = rects_for(d).masks;
  Code painted = 0, colour = 0;  // colour is meaningful only where painted
  int count = 0;
  while (count < limit) {
    const Code right = painted & ~(colour ^ target) & all;
    const Code wrong = all & ~right;
    if (wrong == 0) break;
    int best = 0;
    Code best_mask = 0;
    int best_colour = 0;
    for (const Code m : masks) {
      // colour 0 first, then 1, as in the original loop.
      for (int c = 0; c < 2; ++c) {
        const Code same = c ? target : ~target;  // cells whose target equals colour c
        const int gain = std::popcount(m & wrong & same) - std::popcount(m & right & ~same);
        if (gain > best) {
          best = gain;
          best_mask = m;
          best_colour = c;
        }
      }
    }
    if (best <= 0) break;  // cannot happen for a non-empty wrong set (a 1x1 rectangle gains 1)
    painted |= best_mask;
    colour = best_colour ? (colour | best_mask) : (colour & ~best_mask);
    ++count;
  }
  return count;
}

}  // namespace

int rectangle_complexity(Code v, int d) { return paint(v, d, 1 << 30); }

bool complexity_at_least(Code v, int d, int at_least) {
  if (at_least <= 0) return true;
  return paint(v, d, at_least) >= at_least;
}

}  // namespace tagbench
