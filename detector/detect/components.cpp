#include "detect/components.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace tagbench {
namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];  // path halving
    i = parent[i];
  }
  return i;
}

// Union by index (the smaller root wins) keeps the result independent of the order of unions, and
// with path halving the trees stay shallow enough for this one-pass use.
void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b)
    parent[b] = a;
  else
    parent[a] = b;
}

// The first x in (x0, w) with row[x] != v, or w.
int run_end(const std::uint8_t* row, int x0, int w, std::uint8_t v) {
  int e = x0 + 1;
  const std::uint64_t pattern = std::uint64_t{v} * 0x0101010101010101ULL;
  while (e + 8 <= w) {
    std::uint64_t word;
    std::memcpy(&word, row + e, 8);
    const std::uint64_t diff = word ^ pattern;
    if (diff != 0) {
      // The lowest differing byte in memory order: the lowest set bit on little-endian machines,
      // the highest on big-endian ones.
      if constexpr (std::endian::native == std::endian::little)
        return e + std::countr_zero(diff) / 8;
      else
        return e + std::countl_zero(diff) / 8;
    }
    e += 8;
  }
  while (e < w && row[e] == v) ++e;
  return e;
}

}  // namespace

void connected_components(const TernaryImage& img, ComponentScratch& s, Components& out, bool dark_eight) {
  const int w = img.width, h = img.height;
  out.width = w;
  out.height = h;
  out.count = 0;
  const std::size_t npix = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  auto& runs = out.runs;
  auto& row_start = out.row_start;
  runs.clear();
  row_start.resize(static_cast<std::size_t>(h) + 1);
  if (npix == 0) {
    std::fill(row_start.begin(), row_start.end(), 0);
    out.run_label.clear();
    out.size.clear();
    return;
  }

  // 1. Runs of equal class, row by row; a run's end is looked for 8 bytes at a time (the first byte
  // that differs from the run's value, by the XOR's lowest set byte), so long runs, most of all the
  // unknown ones of flat regions, cost a step per 8 pixels.
  for (int y = 0; y < h; ++y) {
    row_start[static_cast<std::size_t>(y)] = static_cast<std::uint32_t>(runs.size());
    const std::uint8_t* row = img.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    int x = 0;
    while (x < w) {
      const std::uint8_t v = row[x];
      const int e = run_end(row, x, w, v);
      runs.push_back(ClassRun{x, e - 1, v});
      x = e;
    }
  }
  row_start[static_cast<std::size_t>(h)] = static_cast<std::uint32_t>(runs.size());
  const std::size_t nr = runs.size();
  s.parent.resize(nr);
  for (std::size_t i = 0; i < nr; ++i) s.parent[i] = static_cast<std::uint32_t>(i);

  // 2. Join each run with the runs of the row above that touch it: overlapping columns (4-connected,
  // dark, unless dark_eight) or overlapping or diagonally adjacent columns (8-connected: light, or dark_eight).
  for (int y = 1; y < h; ++y) {
    std::uint32_t j = row_start[static_cast<std::size_t>(y) - 1];
    const std::uint32_t jend = row_start[static_cast<std::size_t>(y)];
    for (std::uint32_t i = jend; i < row_start[static_cast<std::size_t>(y) + 1]; ++i) {
      const ClassRun r = runs[i];
      if (r.value == kTernaryUnknown) continue;
      const int slack = (r.value == kTernaryLight) != dark_eight ? 1 : 0;
      while (j < jend && runs[j].x1 < r.x0 - 1) ++j;  // never needed again: later runs start further right
      for (std::uint32_t k = j; k < jend && runs[k].x0 <= r.x1 + slack; ++k) {
        const ClassRun& p = runs[k];
        if (p.value == r.value && p.x1 >= r.x0 - slack) unite(s.parent, i, k);
      }
    }
  }

  // 3. Roots (each run's label) and sizes.
  out.size.assign(nr, 0);
  out.run_label.resize(nr);
  for (std::size_t i = 0; i < nr; ++i) {
    const std::uint32_t root = find_root(s.parent, static_cast<std::uint32_t>(i));
    s.parent[i] = root;  // runs point to smaller indices: a later run under this one finds its root in a step
    const ClassRun& r = runs[i];
    if (r.value == kTernaryUnknown) {
      out.run_label[i] = kNoComponent;
      continue;
    }
    out.run_label[i] = root;
    if (out.size[root] == 0) ++out.count;
    out.size[root] += static_cast<std::uint32_t>(r.x1 - r.x0 + 1);
  }
}

std::uint32_t Components::label_at(int x, int y) const {
  const auto first = runs.begin() + row_start[static_cast<std::size_t>(y)];
  const auto last = runs.begin() + row_start[static_cast<std::size_t>(y) + 1];
  const auto it = std::partition_point(first, last, [x](const ClassRun& r) { return r.x1 < x; });
  return run_label[static_cast<std::size_t>(it - runs.begin())];
}

std::vector<std::uint32_t> label_image(const Components& c) {
  std::vector<std::uint32_t> label(static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height));
  for (int y = 0; y < c.height; ++y)
    for (std::uint32_t i = c.row_start[static_cast<std::size_t>(y)]; i < c.row_start[static_cast<std::size_t>(y) + 1]; ++i)
      std::fill_n(label.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * static_cast<std::size_t>(c.width)) + c.runs[i].x0,
                  c.runs[i].x1 - c.runs[i].x0 + 1, c.run_label[i]);
  return label;
}

Components connected_components(const TernaryImage& img, bool dark_eight) {
  ComponentScratch s;
  Components out;
  connected_components(img, s, out, dark_eight);
  return out;
}

}  // namespace tagbench
