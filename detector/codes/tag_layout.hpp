#pragma once
// The printed layout of a tag: (d+4) x (d+4) cells, an outer white ring, a black ring, then the
// d x d payload (1 = white) in AprilTag 1 order. The black square (the "tag size" of pose
// estimation) is the middle (d+2) x (d+2) cells.
#include <cstdint>
#include <string>
#include <vector>

#include "tag_family.hpp"

namespace tagbench {

struct TagCells {
  int n = 0;                          // cells per side, d + 4
  std::vector<std::uint8_t> white;    // row-major n*n, 1 = white
  bool at(int y, int x) const { return white[static_cast<std::size_t>(y * n + x)] != 0; }
};

// Throws std::out_of_range "id N is out of range for family F (0..M)".
TagCells tag_cells(const TagFamily& family, int id);
TagCells tag_cells_for_code(Code code, int d);

// A printable SVG: the black square's edge is tag_size_mm, the whole tag (d+4)/(d+2) of that.
std::string tag_svg(const TagCells& cells, double tag_size_mm, const std::string& title);

}  // namespace tagbench
