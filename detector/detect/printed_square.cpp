#include "detect/printed_square.hpp"

#include <algorithm>
#include <stdexcept>

#include "detect/homography.hpp"

namespace tagbench {

std::vector<Quad> black_squares_in_printed_squares(std::span<const Quad> quads, const std::vector<bool>& look,
                                                   std::span<const int> payload_widths) {
  if (look.size() != quads.size()) throw std::invalid_argument("black_squares_in_printed_squares: look and quads differ in size");
  std::vector<int> widths;
  for (const int d : payload_widths) {
    if (d < 1) throw std::invalid_argument("black_squares_in_printed_squares: payload width " + std::to_string(d) + " < 1");
    if (std::find(widths.begin(), widths.end(), d) == widths.end()) widths.push_back(d);
  }
  std::vector<Quad> out;
  const Corners square = tag_square_corners();
  for (std::size_t i = 0; i < quads.size(); ++i) {
    if (!look[i]) continue;
    const auto H = tag_homography(quads[i].corners);
    if (!H) continue;
    for (const int d : widths) {
      const double s = static_cast<double>(d + 2) / static_cast<double>(d + 4);
      Quad q = quads[i];
      for (std::size_t k = 0; k < 4; ++k) q.corners[k] = apply_homography(*H, s * square[k]);
      q.observed_perimeter = 0;  // none of its outline was seen: it loses ties in suppress_duplicates
      out.push_back(q);
    }
  }
  return out;
}

}  // namespace tagbench
