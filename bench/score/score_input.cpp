// The scorer's declared conventions (score.hpp).
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "score/score.hpp"

namespace tagbench::bench {

namespace {

constexpr const char* kCornerNames[4] = {"tl", "tr", "br", "bl"};

}  // namespace

std::array<int, 4> parse_corner_order(const std::string& text) {
  std::array<int, 4> order{};
  std::size_t start = 0;
  bool seen[4] = {false, false, false, false};
  for (int k = 0; k < 4; ++k) {
    const std::size_t dash = text.find('-', start);
    if ((k < 3) != (dash != std::string::npos))
      throw std::invalid_argument("corner order '" + text + "': expected four of tl, tr, br, bl joined by '-'");
    const std::string name = text.substr(start, k < 3 ? dash - start : std::string::npos);
    int c = -1;
    for (int i = 0; i < 4; ++i)
      if (name == kCornerNames[i]) c = i;
    if (c < 0 || seen[c])
      throw std::invalid_argument("corner order '" + text + "': expected each of tl, tr, br, bl once, joined by '-'");
    seen[c] = true;
    order[static_cast<std::size_t>(k)] = c;
    start = dash + 1;
  }
  return order;
}

std::string corner_order_name(const std::array<int, 4>& order) {
  std::string s;
  for (std::size_t k = 0; k < 4; ++k) {
    if (k) s += '-';
    s += kCornerNames[order[k]];
  }
  return s;
}

Eigen::Matrix3d parse_tag_frame(const std::string& text) {
  const auto bad = [&] {
    return std::invalid_argument("tag frame '" + text +
                                 "': expected the detector's x, y, z axes as three of x, y, z with signs, e.g. -x,y,-z "
                                 "(a rotation: each axis once, determinant +1)");
  };
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  std::size_t start = 0;
  bool used[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',', start);
    if ((i < 2) != (comma != std::string::npos)) throw bad();
    std::string item = text.substr(start, i < 2 ? comma - start : std::string::npos);
    double sign = 1;
    if (!item.empty() && (item[0] == '-' || item[0] == '+')) {
      sign = item[0] == '-' ? -1 : 1;
      item = item.substr(1);
    }
    if (item.size() != 1 || item[0] < 'x' || item[0] > 'z' || used[item[0] - 'x']) throw bad();
    used[item[0] - 'x'] = true;
    a(i, item[0] - 'x') = sign;
    start = comma + 1;
  }
  if (a.determinant() < 0) throw bad();
  return a;
}

std::string tag_frame_name(const Eigen::Matrix3d& a) {
  std::string s;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      if (a(i, k) != 0) s += std::string(i ? "," : "") + (a(i, k) < 0 ? "-" : "") + static_cast<char>('x' + k);
  return s;
}

Found to_ours(const Found& theirs, const Convention& c) {
  Found f = theirs;
  for (std::size_t k = 0; k < 4; ++k)
    f.corners[static_cast<std::size_t>(c.order[k])] = theirs.corners[k] - Eigen::Vector2d::Constant(c.pixel_offset);
  if (theirs.pose) f.pose->R = theirs.pose->R * c.tag_axes;
  return f;
}

}  // namespace tagbench::bench
