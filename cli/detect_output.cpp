#include "cli/detect_output.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/format.hpp"
#include "tools/json.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

namespace {

// CSV: the same numbers, empty for non-finite; text fields quoted when they need it.
std::string csv_num(double v) { return std::isfinite(v) ? json_number(v) : std::string(); }

}  // namespace

Sink::Sink(const Settings& s, const Detector& det) : s_(s), det_(det), tty_(::isatty(STDERR_FILENO) != 0) {}

void Sink::begin() {
  if (s_.jsonl) return;  // lines only
  if (s_.csv) {
    put("input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,tx,ty,tz,"
        "r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,min_decision_margin,input_gamma\n");
    return;
  }
  const DetectorOptions& o = det_.options();
  std::string h = "{\n  \"tool\": \"tagbench detect\",\n  \"options\": {\"families\": [";
  for (std::size_t i = 0; i < det_.families().size(); ++i)
    h += (i ? ", " : "") + json_string(det_.families()[i].name());
  h += "], \"profile\": " + json_string(s_.profile) +
       ", \"max_hamming\": " + std::to_string(o.max_hamming) +
       ", \"min_decision_margin\": " + json_number(o.min_decision_margin) +
       ", \"half_res\": " + (o.half_resolution ? "true" : "false") +
       ", \"input_gamma\": " + json_number(o.input_gamma) + ", \"camera\": ";
  if (o.camera)
    h += std::string("[") + json_number(o.camera->fx) + ", " + json_number(o.camera->fy) + ", " + json_number(o.camera->cx) +
         ", " + json_number(o.camera->cy) + "]";
  else
    h += "null";
  h += ", \"distortion\": ";
  if (o.distortion) {
    h += "[";
    for (std::size_t i = 0; i < 5; ++i) h += (i ? ", " : "") + json_number((*o.distortion)[i]);
    h += "]";
  } else {
    h += "null";
  }
  h += ", \"tag_size\": " + (o.camera ? json_number(o.tag_size) : std::string("null")) + "},\n  \"images\": [";
  put(h);
}

void Sink::emit(const Outcome& o) {
  if (!o.error.empty()) {
    errors_.push_back(o);
    std::fprintf(stderr, "%stagbench detect: %s: %s\n", tty_ ? "\r\033[K" : "", one_line(o.label, true).c_str(),
                 one_line(o.error, false).c_str());
    std::fflush(stderr);
    if (s_.jsonl) put("{\"image\": " + json_string(o.label) + ", \"error\": " + json_string(o.error) + "}\n");
    return;
  }
  if (s_.jsonl) emit_jsonl(o);
  else if (s_.csv) emit_csv(o);
  else emit_json(o);
}

void Sink::end() {
  if (!s_.csv && !s_.jsonl) {
    std::string t = images_ ? "\n  ],\n  \"errors\": [" : "],\n  \"errors\": [";
    for (std::size_t i = 0; i < errors_.size(); ++i)
      t += std::string(i ? "," : "") + "\n    {\"input\": " + json_string(errors_[i].label) +
           ", \"error\": " + json_string(errors_[i].error) + "}";
    t += errors_.empty() ? "]\n}\n" : "\n  ]\n}\n";
    put(t);
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) throw std::runtime_error("cannot write the output to stdout");
}

std::string Sink::point(const Eigen::Vector2d& p) {
  return std::string("[") + json_number(p.x()) + ", " + json_number(p.y()) + "]";
}

std::string Sink::matrix(const Eigen::Matrix3d& m) {
  std::string s = "[";
  for (int i = 0; i < 3; ++i)
    s += std::string(i ? ", " : "") + "[" + json_number(m(i, 0)) + ", " + json_number(m(i, 1)) + ", " +
         json_number(m(i, 2)) + "]";
  return s + "]";
}

std::string Sink::pose(const PoseSolution& p) {
  return "{\"R\": " + matrix(p.pose.R) + ", \"t\": [" + json_number(p.pose.t.x()) + ", " + json_number(p.pose.t.y()) +
         ", " + json_number(p.pose.t.z()) + "], \"reprojection_rms_px\": " + json_number(p.reprojection_rms_px) +
         (std::isfinite(p.pattern_correlation) ? ", \"pattern_correlation\": " + json_number(p.pattern_correlation) : "") +
         "}";
}

void Sink::emit_json(const Outcome& o) {
  std::string s = images_++ ? ",\n    {" : "\n    {";
  s += "\"input\": " + json_string(o.label);
  if (o.frame_number >= 0) s += ", \"frame\": " + std::to_string(o.frame_number);
  s += ", \"width\": " + std::to_string(o.width) + ", \"height\": " + std::to_string(o.height) +
       ", \"detect_ms\": " + json_number(o.detect_ms) + ", \"detections\": [";
  for (std::size_t i = 0; i < o.detections.size(); ++i) {
    const Detection& d = o.detections[i];
    s += i ? ",\n      {" : "\n      {";
    s += "\"family\": " + json_string(d.family) + ", \"id\": " + std::to_string(d.id) +
         ", \"hamming\": " + std::to_string(d.hamming) + ", \"rotation\": " + std::to_string(d.rotation) +
         ", \"decision_margin\": " + json_number(d.decision_margin) + ",\n       \"corners\": [";
    for (std::size_t k = 0; k < 4; ++k) s += (k ? ", " : "") + point(d.corners[k]);
    s += "], \"center\": " + point(d.center) + ",\n       \"homography\": " + matrix(d.homography);
    if (d.pose) s += ",\n       \"pose\": " + pose(*d.pose);
    if (d.pose_alternative) s += ",\n       \"pose_alternative\": " + pose(*d.pose_alternative);
    if (d.pose_ambiguous) s += ", \"pose_ambiguous\": true";
    const StageTimings& t = d.timings;
    s += ",\n       \"timings_ms\": {\"blur\": " + json_number(t.blur) +
         ", \"gradient\": " + json_number(t.gradient) + ", \"segmentation\": " + json_number(t.segmentation) +
         ", \"line_fit\": " + json_number(t.line_fit) + ", \"quads\": " + json_number(t.quads) +
         ", \"decode\": " + json_number(t.decode) + ", \"pose\": " + json_number(t.pose) +
         ", \"total\": " + json_number(t.total) + "}}";
  }
  s += o.detections.empty() ? "]" : "\n    ]";
  if (!s_.explain.empty()) {
    s += ", \"explain\": [";
    for (std::size_t i = 0; i < o.explained.size(); ++i) s += (i ? ", " : "") + explanation_json(o.explained[i]);
    s += "]";
  }
  s += "}";
  put(s);
}

// One line per image (the format tagbench score reads): the detections' ids, corners and poses.
void Sink::emit_jsonl(const Outcome& o) {
  std::string s = "{\"image\": " + json_string(o.label) + ", \"width\": " + std::to_string(o.width) +
                  ", \"height\": " + std::to_string(o.height) + ", \"ms\": " + json_number(o.detect_ms) +
                  ", \"detections\": [";
  for (std::size_t i = 0; i < o.detections.size(); ++i) {
    const Detection& d = o.detections[i];
    s += std::string(i ? ", " : "") + "{\"family\": " + json_string(d.family) + ", \"id\": " + std::to_string(d.id) +
         ", \"hamming\": " + std::to_string(d.hamming) + ", \"decision_margin\": " + json_number(d.decision_margin) +
         ", \"corners\": [";
    for (std::size_t k = 0; k < 4; ++k) s += (k ? ", " : "") + point(d.corners[k]);
    s += "]";
    if (d.pose)
      s += ", \"pose\": {\"R\": " + matrix(d.pose->pose.R) + ", \"t\": [" + json_number(d.pose->pose.t.x()) + ", " +
           json_number(d.pose->pose.t.y()) + ", " + json_number(d.pose->pose.t.z()) + "]}";
    s += "}";
  }
  s += "]";
  if (!s_.explain.empty()) {  // as in the JSON document
    s += ", \"explain\": [";
    for (std::size_t i = 0; i < o.explained.size(); ++i) s += (i ? ", " : "") + explanation_json(o.explained[i]);
    s += "]";
  }
  put(s + "}\n");
}

void Sink::emit_csv(const Outcome& o) {
  for (const PointExplanation& e : o.explained) {  // CSV has no place for them: stderr, one line each
    std::fprintf(stderr, "%stagbench detect: %s: explain %s: %s: %s\n", tty_ ? "\r\033[K" : "",
                 one_line(o.label, true).c_str(), e.spec.c_str(), e.stage.c_str(), one_line(e.text, false).c_str());
    std::fflush(stderr);
  }
  for (const Detection& d : o.detections) {
    std::vector<std::string> f = {csv_field(o.label), csv_field(d.family), std::to_string(d.id),
                                  std::to_string(d.hamming), std::to_string(d.rotation), csv_num(d.decision_margin)};
    for (const auto& c : d.corners) {
      f.push_back(csv_num(c.x()));
      f.push_back(csv_num(c.y()));
    }
    f.push_back(csv_num(d.center.x()));
    f.push_back(csv_num(d.center.y()));
    if (d.pose) {
      const Pose& p = d.pose->pose;
      for (int i = 0; i < 3; ++i) f.push_back(csv_num(p.t(i)));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f.push_back(csv_num(p.R(i, j)));
      f.push_back(csv_num(d.pose->reprojection_rms_px));
    } else {
      f.resize(f.size() + 13);
    }
    f.push_back(std::to_string(det_.options().max_hamming));
    f.push_back(det_.options().half_resolution ? "1" : "0");
    f.push_back(csv_num(det_.options().min_decision_margin));
    f.push_back(csv_num(det_.options().input_gamma));
    std::string line;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (i) line += ',';
      line += f[i];
    }
    line += '\n';
    put(line);
  }
}

}  // namespace tagbench::cli::detect_cmd
