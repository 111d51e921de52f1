#pragma once
// Shared by the `tagbench detect` tests (test_cli_detect_*.cpp): running the program in one scratch
// folder for the test program, reading its JSON and CSV output, and making test images of 25h9 tags
// placed at known pixel positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tools/json_read.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_detect {

namespace fs = std::filesystem;

// ---- running the program ----------------------------------------------------------------------

using Result = tagbench::testing::CommandResult;

using tagbench::testing::slurp;

inline fs::path scratch_dir() {
  const fs::path d = tagbench::testing::program_scratch("tagbench_cli_detect");
  fs::create_directories(d);
  return d;
}

// A fresh directory for one test.
inline fs::path fresh(const std::string& name) {
  const fs::path d = scratch_dir() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Shell quoting for paths with quotes and backslashes.
inline std::string q(const std::string& s) { return tagbench::testing::shell_quote(s); }
inline std::string q(const fs::path& p) { return q(p.string()); }

inline Result run(const std::string& args) { return tagbench::testing::run_tagbench(args, scratch_dir()); }

inline int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// ---- JSON: the project's reader (tools/json_read), which also checks that the output is valid JSON,
// seen through a small tree with [] access for terse assertions -----------------------------------

struct Json {
  enum Type { kNull, kBool, kNum, kStr, kArr, kObj } type = kNull;
  bool b = false;
  double num = 0;
  std::string str;
  std::vector<Json> arr;
  std::vector<std::pair<std::string, Json>> obj;

  const Json& operator[](const std::string& k) const {
    if (type != kObj) throw std::runtime_error("not an object looking up " + k);
    for (const auto& [key, v] : obj)
      if (key == k) return v;
    throw std::runtime_error("no key " + k);
  }
  const Json& operator[](std::size_t i) const {
    if (type != kArr || i >= arr.size()) throw std::runtime_error("bad array index");
    return arr[i];
  }
  bool has(const std::string& k) const {
    for (const auto& [key, v] : obj)
      if (key == k) return true;
    return false;
  }
  std::size_t size() const { return type == kArr ? arr.size() : obj.size(); }
};

inline Json tree(const tagbench::JsonValue& v) {
  using K = tagbench::JsonValue::Kind;
  Json j;
  switch (v.kind()) {
    case K::kNull: break;
    case K::kBool: j.type = Json::kBool, j.b = v.boolean("value"); break;
    case K::kNumber: j.type = Json::kNum, j.num = v.number("value"); break;
    case K::kString: j.type = Json::kStr, j.str = v.string("value"); break;
    case K::kArray:
      j.type = Json::kArr;
      for (const auto& e : v.array("value")) j.arr.push_back(tree(e));
      break;
    case K::kObject:
      j.type = Json::kObj;
      for (const auto& [k, e] : v.members("value")) j.obj.emplace_back(k, tree(e));
      break;
  }
  return j;
}

inline Json parse_json(const std::string& s) { return tree(tagbench::parse_json(s)); }

// ---- CSV ---------------------------------------------------------------------------------------

inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') f.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else f.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      f.emplace_back();
    } else {
      f.back() += c;
    }
  }
  return f;
}

// Rows as maps from the header's column names.
inline std::vector<std::map<std::string, std::string>> parse_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const auto header = split_csv_line(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto f = split_csv_line(line);
    EXPECT_EQ(f.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) row[header[i]] = f[i];
    rows.push_back(row);
  }
  return rows;
}

// ---- test images -------------------------------------------------------------------------------

inline constexpr int kCells = 9;  // 25h9: d = 5, (d + 4) cells a side, black square = cells 1..7

// Tag `id` of 25h9 rendered by `tagbench render` at k pixels a cell.
inline cv::Mat rendered_tag(int id, int k) {
  const fs::path p = scratch_dir() / ("tag25h9_" + std::to_string(id) + "_" + std::to_string(k) + ".png");
  if (!fs::exists(p)) {
    const Result r = run("render --family 25h9 --id " + std::to_string(id) + " --px-per-cell " + std::to_string(k) +
                         " -o " + q(p));
    EXPECT_EQ(r.code, 0) << r.err;
  }
  const cv::Mat t = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(t.rows, kCells * k);
  return t;
}

// The tag pasted at (ox, oy) into a mid-gray canvas.
inline cv::Mat padded(const cv::Mat& tag, int ox, int oy, int w, int h) {
  cv::Mat c(h, w, CV_8UC1, cv::Scalar(128));
  tag.copyTo(c(cv::Rect(ox, oy, tag.cols, tag.rows)));
  return c;
}

using Pt = std::array<double, 2>;

// The black square's outer corners of an upright tag with k px a cell pasted at (ox, oy): pixel
// centres at integers, so the square spans [ox + k - 0.5, ox + 8k - 0.5]. Printed TL, TR, BR, BL.
inline std::array<Pt, 4> upright_corners(int ox, int oy, int k) {
  const double a = ox + k - 0.5, b = ox + (kCells - 1) * k - 0.5;
  const double c = oy + k - 0.5, d = oy + (kCells - 1) * k - 0.5;
  return {Pt{a, c}, Pt{b, c}, Pt{b, d}, Pt{a, d}};
}

inline void write_png(const fs::path& p, const cv::Mat& m) { ASSERT_TRUE(cv::imwrite(p.string(), m)) << p; }

inline void expect_corners(const Json& det, const std::array<Pt, 4>& want, double tol) {
  const Json& c = det["corners"];
  ASSERT_EQ(c.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[i][0].num, want[i][0], tol) << "corner " << i << " x";
    EXPECT_NEAR(c[i][1].num, want[i][1], tol) << "corner " << i << " y";
  }
}

}  // namespace test_cli_detect
