// The scorer's inputs: detection lines and declared conventions (score.hpp).
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include "score/score.hpp"
#include "tools/json_read.hpp"

namespace tagbench::bench {

namespace {

constexpr const char* kCornerNames[4] = {"tl", "tr", "br", "bl"};

Found read_found(const JsonValue& j, const std::string& what) {
  Found f;
  f.family = j.at("family", what).string(what + ": family");
  f.id = j.at("id", what).integer(what + ": id");
  const auto& corners = j.at("corners", what).array(what + ": corners");
  if (corners.size() != 4) throw JsonError(what + ": corners: expected 4 points [x, y]");
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& p = corners[k].array(what + ": corners");
    if (p.size() != 2) throw JsonError(what + ": corners: expected 4 points [x, y]");
    f.corners[k] = Eigen::Vector2d(p[0].number(what + ": corners"), p[1].number(what + ": corners"));
  }
  if (const JsonValue* m = j.find("decision_margin"); m && !m->is_null())
    f.decision_margin = m->number(what + ": decision_margin");
  if (const JsonValue* h = j.find("hamming"); h && !h->is_null()) f.hamming = h->integer(what + ": hamming");
  if (const JsonValue* p = j.find("pose"); p && !p->is_null()) {
    Pose pose;
    const auto& rows = p->at("R", what + ": pose").array(what + ": pose.R");
    if (rows.size() != 3) throw JsonError(what + ": pose.R: expected 3 rows of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const auto& r = rows[static_cast<std::size_t>(i)].array(what + ": pose.R");
      if (r.size() != 3) throw JsonError(what + ": pose.R: expected 3 rows of 3 numbers");
      for (int k = 0; k < 3; ++k) pose.R(i, k) = r[static_cast<std::size_t>(k)].number(what + ": pose.R");
    }
    const auto& t = p->at("t", what + ": pose").array(what + ": pose.t");
    if (t.size() != 3) throw JsonError(what + ": pose.t: expected 3 numbers");
    for (int i = 0; i < 3; ++i) pose.t(i) = t[static_cast<std::size_t>(i)].number(what + ": pose.t");
    f.pose = pose;
  }
  return f;
}

}  // namespace

std::vector<ImageDetections> parse_detection_lines(const std::string& text, const std::string& source) {
  std::vector<ImageDetections> out;
  std::size_t start = 0, line = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view l(text.data() + start, end - start);
    ++line;
    start = end + 1;
    if (l.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    const std::string where = source + " line " + std::to_string(line);
    try {
      const JsonValue j = parse_json(l);
      ImageDetections d;
      d.line = line;
      d.image = j.at("image", "the line").string("image");
      if (d.image.empty()) throw JsonError("image: empty");
      if (const JsonValue* ms = j.find("ms"); ms && !ms->is_null()) d.ms = ms->number("ms");
      if (const JsonValue* e = j.find("error"); e && !e->is_null()) {
        d.error = e->string("error");
      } else {
        const auto& dets = j.at("detections", "the line").array("detections");
        for (std::size_t i = 0; i < dets.size(); ++i) d.found.push_back(read_found(dets[i], "detections[" + std::to_string(i) + "]"));
      }
      out.push_back(std::move(d));
    } catch (const std::exception& e) {
      throw std::runtime_error(where + ": " + e.what());
    }
  }
  return out;
}

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
  for (std::size_t k = 0; k < 4; ++k) s += (k ? "-" : "") + std::string(kCornerNames[order[k]]);
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
