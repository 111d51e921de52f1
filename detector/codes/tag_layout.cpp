#include "codes/tag_layout.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace tagbench {

TagCells tag_cells_for_code(Code code, int d) {
  TagCells t;
  t.n = d + 4;
  t.white.assign(static_cast<std::size_t>(t.n * t.n), 0);
  for (int y = 0; y < t.n; ++y)
    for (int x = 0; x < t.n; ++x) {
      bool w;
      if (y == 0 || x == 0 || y == t.n - 1 || x == t.n - 1) w = true;        // white ring
      else if (y == 1 || x == 1 || y == t.n - 2 || x == t.n - 2) w = false;  // black ring
      else w = (code >> cell_bit(d, y - 2, x - 2)) & 1;
      t.white[static_cast<std::size_t>(y * t.n + x)] = w ? 1 : 0;
    }
  return t;
}

TagCells tag_cells(const TagFamily& family, int id) {
  if (id < 0 || static_cast<std::size_t>(id) >= family.size())
    throw std::out_of_range("id " + std::to_string(id) + " is out of range for family " + family.name() + " (0.." +
                            std::to_string(family.size() - 1) + ")");
  return tag_cells_for_code(family.codes()[static_cast<std::size_t>(id)], family.payload_width());
}

std::string tag_svg(const TagCells& cells, double tag_size_mm, const std::string& title) {
  const double cell = tag_size_mm / (cells.n - 2);
  const double total = cell * cells.n;
  std::ostringstream o;
  o.precision(6);
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << total << "mm\" height=\"" << total
    << "mm\" viewBox=\"0 0 " << cells.n << " " << cells.n << "\" shape-rendering=\"crispEdges\">\n"
    << "<title>" << title << " (black square " << tag_size_mm << " mm)</title>\n"
    << "<rect x=\"0\" y=\"0\" width=\"" << cells.n << "\" height=\"" << cells.n << "\" fill=\"#fff\"/>\n";
  // One rectangle per horizontal run of black cells keeps the file small and seamless.
  for (int y = 0; y < cells.n; ++y)
    for (int x = 0; x < cells.n;) {
      if (cells.at(y, x)) { ++x; continue; }
      int e = x;
      while (e < cells.n && !cells.at(y, e)) ++e;
      o << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"" << e - x << "\" height=\"1\" fill=\"#000\"/>\n";
      x = e;
    }
  o << "</svg>\n";
  return o.str();
}

}  // namespace tagbench
