// Detection lines (detection_lines.hpp).
#include "external/detection_lines.hpp"

#include <stdexcept>

#include "tools/json_read.hpp"

namespace tagbench::bench {

namespace {

Found read_found(const JsonValue& j, const std::string& what) {
  Found f;
  f.family = j.at("family", what).string(what + ": family");
  f.id = j.at("id", what).integer(what + ": id");
  if (f.id < 0) throw JsonError(what + ": id: " + std::to_string(f.id) + " is negative");
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
    // Orthonormal to printing precision (a detector's six significant digits are 1e-5 off): scored
    // as a rotation, anything else would give a meaningless angle.
    const double off = rotation_defect(pose.R);
    if (!(off <= 1e-3)) throw JsonError(what + ": pose.R: not a rotation (R^T R differs from I by " + std::to_string(off) + ")");
    const auto& t = p->at("t", what + ": pose").array(what + ": pose.t");
    if (t.size() != 3) throw JsonError(what + ": pose.t: expected 3 numbers");
    for (int i = 0; i < 3; ++i) pose.t(i) = t[static_cast<std::size_t>(i)].number(what + ": pose.t");
    f.pose = pose;
  }
  return f;
}

}  // namespace

ImageDetections parse_detection_line(std::string_view l) {
  const JsonValue j = parse_json(l);
  ImageDetections d;
  d.image = j.at("image", "the line").string("image");
  if (d.image.empty()) throw JsonError("image: empty");
  if (const JsonValue* ms = j.find("ms"); ms && !ms->is_null()) {
    d.ms = ms->number("ms");
    if (!(d.ms >= 0)) throw JsonError("ms: " + std::to_string(d.ms) + " is negative (milliseconds)");
  }
  if (const JsonValue* e = j.find("error"); e && !e->is_null()) {
    d.error = e->string("error");
  } else {
    const auto& dets = j.at("detections", "the line").array("detections");
    for (std::size_t i = 0; i < dets.size(); ++i) d.found.push_back(read_found(dets[i], "detections[" + std::to_string(i) + "]"));
  }
  return d;
}

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
    try {
      out.push_back(parse_detection_line(l));
      out.back().line = line;
    } catch (const std::exception& e) {
      throw std::runtime_error(source + " line " + std::to_string(line) + ": " + e.what());
    }
  }
  return out;
}

}  // namespace tagbench::bench
