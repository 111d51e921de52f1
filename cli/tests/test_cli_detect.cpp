// `tagbench detect` end to end: JSON and CSV output (checked against tags placed at known pixel
// positions and at a known pose), batches (directories, a corrupt file among good ones, input order
// with several threads), videos, --draw, --debug-dir, and the bad-input rules.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "tools/json_read.hpp"
#include "kill_run.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_detect {

namespace fs = std::filesystem;

namespace {

// ---- running the program ----------------------------------------------------------------------

using Result = tagbench::testing::CommandResult;

using tagbench::testing::slurp;

fs::path scratch_dir() {
  const fs::path d = tagbench::testing::program_scratch("tagbench_cli_detect");
  fs::create_directories(d);
  return d;
}

// A fresh directory for one test.
fs::path fresh(const std::string& name) {
  const fs::path d = scratch_dir() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Shell quoting for paths with quotes and backslashes.
std::string q(const std::string& s) { return tagbench::testing::shell_quote(s); }
std::string q(const fs::path& p) { return q(p.string()); }

Result run(const std::string& args) { return tagbench::testing::run_tagbench(args, scratch_dir()); }

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

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

Json tree(const tagbench::JsonValue& v) {
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

Json parse_json(const std::string& s) { return tree(tagbench::parse_json(s)); }

// ---- CSV ---------------------------------------------------------------------------------------

std::vector<std::string> split_csv_line(const std::string& line) {
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
std::vector<std::map<std::string, std::string>> parse_csv(const std::string& text) {
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

constexpr int kCells = 9;  // 25h9: d = 5, (d + 4) cells a side, black square = cells 1..7

// Tag `id` of 25h9 rendered by `tagbench render` at k pixels a cell.
cv::Mat rendered_tag(int id, int k) {
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
cv::Mat padded(const cv::Mat& tag, int ox, int oy, int w, int h) {
  cv::Mat c(h, w, CV_8UC1, cv::Scalar(128));
  tag.copyTo(c(cv::Rect(ox, oy, tag.cols, tag.rows)));
  return c;
}

using Pt = std::array<double, 2>;

// The black square's outer corners of an upright tag with k px a cell pasted at (ox, oy): pixel
// centres at integers, so the square spans [ox + k - 0.5, ox + 8k - 0.5]. Printed TL, TR, BR, BL.
std::array<Pt, 4> upright_corners(int ox, int oy, int k) {
  const double a = ox + k - 0.5, b = ox + (kCells - 1) * k - 0.5;
  const double c = oy + k - 0.5, d = oy + (kCells - 1) * k - 0.5;
  return {Pt{a, c}, Pt{b, c}, Pt{b, d}, Pt{a, d}};
}

void write_png(const fs::path& p, const cv::Mat& m) { ASSERT_TRUE(cv::imwrite(p.string(), m)) << p; }

void expect_corners(const Json& det, const std::array<Pt, 4>& want, double tol) {
  const Json& c = det["corners"];
  ASSERT_EQ(c.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[i][0].num, want[i][0], tol) << "corner " << i << " x";
    EXPECT_NEAR(c[i][1].num, want[i][1], tol) << "corner " << i << " y";
  }
}

}  // namespace

// ---- tests -------------------------------------------------------------------------------------

TEST(CliDetect, Help) {
  const Result r = run("detect --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("usage: tagbench detect"), std::string::npos);
  EXPECT_NE(r.out.find("\"pose_alternative\""), std::string::npos) << "the JSON schema is part of the help";
  EXPECT_NE(run("--help").out.find("detect"), std::string::npos);
}

TEST(CliDetect, FamilyIdAndCornersInJsonAndCsv) {
  const fs::path dir = fresh("corners");
  constexpr int k = 12, ox = 70, oy = 50;
  const cv::Mat tag = rendered_tag(7, k);
  write_png(dir / "upright.png", padded(tag, ox, oy, 320, 300));
  // The same tag turned a quarter clockwise: the printed top-left corner is now at the top right.
  cv::Mat turned;
  cv::rotate(tag, turned, cv::ROTATE_90_CLOCKWISE);
  write_png(dir / "turned.png", padded(turned, ox, oy, 320, 300));

  const Result r = run("detect --family 25h9 " + q(dir / "upright.png") + " " + q(dir / "turned.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const Json j = parse_json(r.out);
  EXPECT_EQ(j["tool"].str, "tagbench detect");
  EXPECT_EQ(j["options"]["families"][0].str, "25h9");
  EXPECT_EQ(j["options"]["max_hamming"].num, 3);  // the default profile's cap; by family 25h9 gets 2
  EXPECT_EQ(j["options"]["min_decision_margin"].num, 0);
  EXPECT_EQ(j["options"]["camera"].type, Json::kNull);
  EXPECT_EQ(j["errors"].size(), 0u);
  ASSERT_EQ(j["images"].size(), 2u);
  const auto up = upright_corners(ox, oy, k);
  for (std::size_t n = 0; n < 2; ++n) {
    const Json& img = j["images"][n];
    EXPECT_EQ(img["input"].str, (dir / (n == 0 ? "upright.png" : "turned.png")).string());
    EXPECT_EQ(img["width"].num, 320);
    EXPECT_EQ(img["height"].num, 300);
    ASSERT_EQ(img["detections"].size(), 1u) << r.out;
    const Json& d = img["detections"][0];
    EXPECT_EQ(d["family"].str, "25h9");
    EXPECT_EQ(d["id"].num, 7);
    EXPECT_EQ(d["hamming"].num, 0);
    EXPECT_FALSE(d.has("pose")) << "no pose without a camera";
    EXPECT_GT(d["decision_margin"].num, 0.5);
    EXPECT_GE(d["timings_ms"]["total"].num, d["timings_ms"]["quads"].num);
    // Corners in printed order: a quarter turn clockwise moves printed TL to the image's top right.
    const std::array<Pt, 4> want = n == 0 ? up : std::array<Pt, 4>{up[1], up[2], up[3], up[0]};
    expect_corners(d, want, 0.3);
    EXPECT_NEAR(d["center"][0].num, ox + kCells * k / 2.0 - 0.5, 0.3);
    EXPECT_NEAR(d["center"][1].num, oy + kCells * k / 2.0 - 0.5, 0.3);
    // The homography maps the tag square's (-1,-1) onto the printed top-left corner.
    const Json& H = d["homography"];
    const double w = H[2][0].num * -1 + H[2][1].num * -1 + H[2][2].num;
    EXPECT_NEAR((H[0][0].num * -1 + H[0][1].num * -1 + H[0][2].num) / w, want[0][0], 0.3);
    EXPECT_NEAR((H[1][0].num * -1 + H[1][1].num * -1 + H[1][2].num) / w, want[0][1], 0.3);
  }
  EXPECT_NE(j["images"][0]["detections"][0]["rotation"].num, j["images"][1]["detections"][0]["rotation"].num);

  // CSV: the same detections, one row each, settings as columns, pose columns empty.
  const Result c = run("detect --family 25h9 --max-hamming 2 --format csv " + q(dir / "upright.png") + " " +
                       q(dir / "turned.png"));
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_EQ(c.out.rfind("input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,tx,ty,tz,"
                        "r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,"
                        "min_decision_margin,input_gamma\n",
                        0),
            0u);
  const auto rows = parse_csv(c.out);
  ASSERT_EQ(rows.size(), 2u);
  for (std::size_t n = 0; n < 2; ++n) {
    const auto& row = rows[n];
    EXPECT_EQ(row.at("family"), "25h9");
    EXPECT_EQ(row.at("id"), "7");
    EXPECT_EQ(row.at("max_hamming"), "2");
    EXPECT_EQ(row.at("half_res"), "0");
    EXPECT_EQ(row.at("min_decision_margin"), "0");
    EXPECT_EQ(row.at("tz"), "");
    EXPECT_EQ(row.at("r22"), "");
    const std::array<Pt, 4> want = n == 0 ? up : std::array<Pt, 4>{up[1], up[2], up[3], up[0]};
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(std::stod(row.at("x" + std::to_string(i))), want[static_cast<std::size_t>(i)][0], 0.3);
      EXPECT_NEAR(std::stod(row.at("y" + std::to_string(i))), want[static_cast<std::size_t>(i)][1], 0.3);
    }
  }
}

TEST(CliDetect, ColourAnd16BitInputsAreConverted) {
  const fs::path dir = fresh("depths");
  constexpr int k = 12, ox = 30, oy = 40;
  const cv::Mat g = padded(rendered_tag(3, k), ox, oy, 200, 190);
  cv::Mat bgr, g16;
  cv::cvtColor(g, bgr, cv::COLOR_GRAY2BGR);
  g.convertTo(g16, CV_16U, 257.0);
  write_png(dir / "colour.png", bgr);
  write_png(dir / "deep.png", g16);
  write_png(dir / "photo.jpg", bgr);
  const Result r = run("detect --family 25h9 --format json " + q(dir));
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = parse_json(r.out);
  ASSERT_EQ(j["images"].size(), 3u);
  for (std::size_t n = 0; n < 3; ++n) {
    ASSERT_EQ(j["images"][n]["detections"].size(), 1u) << j["images"][n]["input"].str;
    EXPECT_EQ(j["images"][n]["detections"][0]["id"].num, 3);
    expect_corners(j["images"][n]["detections"][0], upright_corners(ox, oy, k), n == 2 ? 0.5 : 0.3);
  }
}

TEST(CliDetect, PoseMatchesTheKnownDistance) {
  const fs::path dir = fresh("pose");
  constexpr int k = 16;
  constexpr double fx = 800, fy = 780, cx = 330, cy = 236, s = 0.1;
  const cv::Mat tag = rendered_tag(11, k);
  // Tag pixel (u, v) -> tag frame (metres): the black square [k - 0.5, 8k - 0.5] is [-s/2, s/2].
  const double m = s / ((kCells - 2) * k), uc = kCells * k / 2.0 - 0.5;
  const cv::Matx33d A(m, 0, -m * uc, 0, m, -m * uc, 0, 0, 1);
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(0.35, -0.25, 0.1), R);
  const cv::Vec3d t(0.03, -0.02, 0.62);
  const cv::Matx33d K(fx, 0, cx, 0, fy, cy, 0, 0, 1);
  const cv::Matx33d Rt(R(0, 0), R(0, 1), t[0], R(1, 0), R(1, 1), t[1], R(2, 0), R(2, 1), t[2]);
  const cv::Matx33d H = K * Rt * A;  // tag pixels -> image pixels
  cv::Mat img;
  cv::warpPerspective(tag, img, cv::Mat(H), cv::Size(640, 480), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar(128));
  write_png(dir / "posed.png", img);

  const std::string cam = " --camera " + std::to_string(fx) + "," + std::to_string(fy) + "," + std::to_string(cx) +
                          "," + std::to_string(cy) + " --tag-size 0.1 ";
  const Result r = run("detect --family 25h9" + cam + q(dir / "posed.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = parse_json(r.out);
  EXPECT_EQ(j["options"]["camera"][1].num, fy);
  EXPECT_EQ(j["options"]["tag_size"].num, 0.1);
  ASSERT_EQ(j["images"][0]["detections"].size(), 1u) << r.out;
  const Json& d = j["images"][0]["detections"][0];
  EXPECT_EQ(d["id"].num, 11);
  ASSERT_TRUE(d.has("pose"));
  const Json& pose = d["pose"];
  EXPECT_NEAR(pose["t"][2].num, t[2], 0.02 * t[2]);
  EXPECT_NEAR(pose["t"][0].num, t[0], 0.003);
  EXPECT_NEAR(pose["t"][1].num, t[1], 0.003);
  double dot = 0;  // trace(R_true^T R) = 1 + 2 cos(angle)
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t c = 0; c < 3; ++c) dot += R(static_cast<int>(i), static_cast<int>(c)) * pose["R"][i][c].num;
  EXPECT_GT(dot, 1 + 2 * std::cos(3.0 * CV_PI / 180)) << "orientation within 3 degrees";
  EXPECT_LT(pose["reprojection_rms_px"].num, 0.5);
  // The printed top-left corner is the projection of (-s/2, -s/2, 0).
  const cv::Vec3d tl = K * (R * cv::Vec3d(-s / 2, -s / 2, 0) + t);
  EXPECT_NEAR(d["corners"][0][0].num, tl[0] / tl[2], 0.5);
  EXPECT_NEAR(d["corners"][0][1].num, tl[1] / tl[2], 0.5);

  const Result c = run("detect --family 25h9 --format csv" + cam + q(dir / "posed.png"));
  ASSERT_EQ(c.code, 0) << c.err;
  const auto rows = parse_csv(c.out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(std::stod(rows[0].at("tz")), t[2], 0.02 * t[2]);
  EXPECT_NEAR(std::stod(rows[0].at("r00")), R(0, 0), 0.05);

  // JSON lines (--format jsonl): the same detection, corners and pose, one line per image; an
  // unreadable input is a line with its error (and exit status 1).
  std::ofstream(dir / "broken.png") << "not a png";
  const Result l = run("detect --family 25h9 --format jsonl" + cam + q(dir / "posed.png") + " " + q(dir / "broken.png"));
  EXPECT_EQ(l.code, 1);
  const auto nl = l.out.find('\n');
  ASSERT_NE(nl, std::string::npos);
  const Json line = parse_json(l.out.substr(0, nl));
  EXPECT_EQ(line["image"].str, (dir / "posed.png").string());
  ASSERT_EQ(line["detections"].size(), 1u);
  EXPECT_EQ(line["detections"][0]["id"].num, 11);
  for (std::size_t k = 0; k < 4; ++k)
    for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(line["detections"][0]["corners"][k][i].num, d["corners"][k][i].num);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line["detections"][0]["pose"]["t"][i].num, pose["t"][i].num);
  const Json bad = parse_json(l.out.substr(nl + 1, l.out.size() - nl - 2));
  EXPECT_EQ(bad["image"].str, (dir / "broken.png").string());
  EXPECT_FALSE(bad["error"].str.empty());
  EXPECT_EQ(l.out.size(), l.out.find('\n', nl + 1) + 1) << "two lines";

  // The drawing shows the pose axes: x red from the tag centre.
  const fs::path drawn = dir / "drawn.png";
  ASSERT_EQ(run("detect --family 25h9" + cam + q(dir / "posed.png") + " --draw " + q(drawn)).code, 0);
  const cv::Mat pic = cv::imread(drawn.string(), cv::IMREAD_COLOR);
  ASSERT_EQ(pic.size(), img.size());
  const cv::Vec3d xe = K * (R * cv::Vec3d(0.45 * s, 0, 0) + t);  // near the end of the x axis (s/2 long)
  const cv::Vec3b px = pic.at<cv::Vec3b>(static_cast<int>(std::lround(xe[1] / xe[2])), static_cast<int>(std::lround(xe[0] / xe[2])));
  EXPECT_GT(px[2], 200) << "red x axis";
  EXPECT_LT(px[1], 80);
  EXPECT_LT(px[0], 80);
}

TEST(CliDetect, DirectoryWithACorruptFile) {
  const fs::path dir = fresh("batch");
  constexpr int k = 12;
  fs::create_directories(dir / "sub");
  write_png(dir / "a.png", padded(rendered_tag(1, k), 20, 30, 180, 170));
  write_png(dir / "sub" / "b.png", padded(rendered_tag(2, k), 40, 10, 190, 160));
  std::ofstream(dir / "c.png") << "this is not a PNG file";
  std::ofstream(dir / "notes.txt") << "not an image: skipped";
  const fs::path out = scratch_dir() / "batch_drawn";
  fs::remove_all(out);

  const Result r = run("detect --family 25h9 " + q(dir) + " --draw " + q(out));
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find((dir / "c.png").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot decode"), std::string::npos) << r.err;
  const Json j = parse_json(r.out);
  ASSERT_EQ(j["images"].size(), 2u);
  EXPECT_EQ(j["images"][0]["input"].str, (dir / "a.png").string());  // sorted: a.png, c.png, sub/b.png
  EXPECT_EQ(j["images"][1]["input"].str, (dir / "sub" / "b.png").string());
  EXPECT_EQ(j["images"][0]["detections"][0]["id"].num, 1);
  EXPECT_EQ(j["images"][1]["detections"][0]["id"].num, 2);
  ASSERT_EQ(j["errors"].size(), 1u);
  EXPECT_EQ(j["errors"][0]["input"].str, (dir / "c.png").string());
  // Several inputs: --draw is a directory with one picture per good input, none for the bad one.
  EXPECT_TRUE(fs::exists(out / "a.png"));
  EXPECT_TRUE(fs::exists(out / "b.png"));
  EXPECT_FALSE(fs::exists(out / "c.png"));
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(out)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 2u) << "no temporaries left behind";
}

TEST(CliDetect, ThreadsKeepTheInputOrder) {
  const fs::path dir = fresh("order");
  constexpr int k = 10;
  for (int i = 0; i < 8; ++i)  // different ids and positions, and sizes so the work differs
    write_png(dir / ("img" + std::to_string(i) + ".png"),
              padded(rendered_tag(i, k), 5 + 7 * i, 9 + 3 * i, 120 + 40 * (i % 3) + 7 * i, 140 + 9 * i));
  const Result one = run("detect --family 25h9 --format csv --threads 1 " + q(dir));
  const Result three = run("detect --family 25h9 --format csv --threads 3 " + q(dir));
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(three.code, 0) << three.err;
  EXPECT_EQ(one.out, three.out);
  const auto rows = parse_csv(three.out);
  ASSERT_EQ(rows.size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(rows[static_cast<std::size_t>(i)].at("id"), std::to_string(i));
}

TEST(CliDetect, DrawWritesAPictureOfTheInputSize) {
  const fs::path dir = fresh("draw");
  constexpr int k = 12, ox = 60, oy = 45;
  const cv::Mat in = padded(rendered_tag(5, k), ox, oy, 260, 230);
  write_png(dir / "in.png", in);
  const fs::path out = dir / "out.png";
  const Result r = run("detect --family 25h9 " + q(dir / "in.png") + " --draw " + q(out));
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat pic = cv::imread(out.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(pic.cols, in.cols);
  ASSERT_EQ(pic.rows, in.rows);
  ASSERT_EQ(pic.channels(), 3);
  // Outline: coloured pixels on the middle of the top edge; a dot of the outline's colour (cyan for
  // the first detection) on the printed top-left corner, none on the others.
  const auto up = upright_corners(ox, oy, k);
  const cv::Vec3b edge = pic.at<cv::Vec3b>(static_cast<int>(std::lround(up[0][1])),
                                           static_cast<int>(std::lround((up[0][0] + up[1][0]) / 2)));
  EXPECT_FALSE(edge[0] == edge[1] && edge[1] == edge[2]) << "the outline is coloured";
  const cv::Vec3b tl = pic.at<cv::Vec3b>(static_cast<int>(std::lround(up[0][1])), static_cast<int>(std::lround(up[0][0])));
  EXPECT_GT(tl[0], 200);
  EXPECT_GT(tl[1], 200);
  EXPECT_LT(tl[2], 80);
  const cv::Vec3b br = pic.at<cv::Vec3b>(static_cast<int>(std::lround(up[2][1])) - 3, static_cast<int>(std::lround(up[2][0])) - 3);
  EXPECT_LT(br[0], 60) << "inside the black square near the bottom-right corner: no dot";
  // Away from the tag the picture is the input.
  EXPECT_EQ(pic.at<cv::Vec3b>(5, 5), cv::Vec3b(128, 128, 128));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << "temporary left: " << e.path();

  // JPEG output, and an unknown picture extension is a usage error.
  ASSERT_EQ(run("detect --family 25h9 " + q(dir / "in.png") + " --draw " + q(dir / "out.jpg")).code, 0);
  EXPECT_EQ(cv::imread((dir / "out.jpg").string()).cols, in.cols);
  const Result bad = run("detect --family 25h9 " + q(dir / "in.png") + " --draw " + q(dir / "out.gif"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_FALSE(fs::exists(dir / "out.gif"));
}

TEST(CliDetect, DebugDirWritesTheSixStages) {
  const fs::path dir = fresh("debug");
  constexpr int k = 12, ox = 50, oy = 40;
  write_png(dir / "in.png", padded(rendered_tag(9, k), ox, oy, 240, 200));
  const char* stages[] = {"gradient_magnitude", "gradient_direction", "clusters", "segments", "quads", "samples"};
  for (const bool half : {false, true}) {
    const fs::path dbg = dir / (half ? "dbg_half" : "dbg");
    const Result r = run("detect --profile paper --family 25h9 " + q(dir / "in.png") + " --debug-dir " + q(dbg) +
                         (half ? " --half-res" : ""));
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(parse_json(r.out)["images"][0]["detections"].size(), 1u);
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dbg)) files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 6u);  // no threshold or boundaries picture: the paper profile has no threshold stage
    EXPECT_FALSE(fs::exists(dbg / "in_threshold.png"));
    for (const char* s : stages) {
      const cv::Mat m = cv::imread((dbg / (std::string("in_") + s + ".png")).string(), cv::IMREAD_COLOR);
      ASSERT_FALSE(m.empty()) << s;
      // The gradient pictures are at the segmentation's resolution, the others at the input's.
      const bool seg_res = std::string(s).rfind("gradient", 0) == 0 || std::string(s) == "clusters";
      EXPECT_EQ(m.cols, half && seg_res ? 120 : 240) << s;
      EXPECT_EQ(m.rows, half && seg_res ? 100 : 200) << s;
    }
  }
  const fs::path dbg = dir / "dbg";
  const cv::Mat mag = cv::imread((dbg / "in_gradient_magnitude.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat hue = cv::imread((dbg / "in_gradient_direction.png").string(), cv::IMREAD_COLOR);
  const cv::Mat clusters = cv::imread((dbg / "in_clusters.png").string(), cv::IMREAD_COLOR);
  const cv::Mat samples = cv::imread((dbg / "in_samples.png").string(), cv::IMREAD_COLOR);
  // Flat background: no gradient, black direction and no cluster; on the black square's left edge
  // (x = ox + k - 0.5) a strong gradient, a colour, and a cluster.
  const int ey = oy + 4 * k, ex = ox + k;
  EXPECT_EQ(mag.at<std::uint8_t>(5, 5), 0);
  EXPECT_EQ(hue.at<cv::Vec3b>(5, 5), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(clusters.at<cv::Vec3b>(5, 5), cv::Vec3b(0, 0, 0));
  EXPECT_GT(std::max(mag.at<std::uint8_t>(ey, ex), mag.at<std::uint8_t>(ey, ex - 1)), 100);
  const auto coloured = [](const cv::Mat& m, int y, int x) { return m.at<cv::Vec3b>(y, x) != cv::Vec3b(0, 0, 0); };
  EXPECT_TRUE(coloured(hue, ey, ex) || coloured(hue, ey, ex - 1));
  EXPECT_TRUE(coloured(clusters, ey, ex) || coloured(clusters, ey, ex - 1));
  // The segment along the black square's top edge has its notch toward the light side: up, into
  // the white ring, and nothing below it inside the (dimmed, still black) square.
  const cv::Mat segs = cv::imread((dbg / "in_segments.png").string(), cv::IMREAD_COLOR);
  const int xm = ox + kCells * k / 2, top = oy + k;
  int above = 0, below = 0;
  for (int x = xm - 2; x <= xm + 2; ++x)
    for (int dy = 2; dy <= 6; ++dy) {
      const cv::Vec3b a = segs.at<cv::Vec3b>(top - dy, x), b = segs.at<cv::Vec3b>(top + dy, x);
      above += std::abs(a[0] - 127) > 8 || std::abs(a[1] - 127) > 8 || std::abs(a[2] - 127) > 8;
      below += b != cv::Vec3b(0, 0, 0);
    }
  EXPECT_GT(above, 2) << "a notch above the black square's top edge";
  EXPECT_EQ(below, 0) << "no notch into the black square";
  // Yellow payload sample dots exist (B low, G and R high); the input has no colour at all.
  int yellow = 0;
  for (int y = 0; y < samples.rows; ++y)
    for (int x = 0; x < samples.cols; ++x) {
      const cv::Vec3b p = samples.at<cv::Vec3b>(y, x);
      yellow += p[0] < 60 && p[1] > 200 && p[2] > 200;
    }
  EXPECT_GT(yellow, 25) << "25 payload cells";
  // Only the detected tag's samples: every yellow dot lies within the tag's payload area (cells 2..6).
  for (int y = 0; y < samples.rows; ++y)
    for (int x = 0; x < samples.cols; ++x) {
      const cv::Vec3b p = samples.at<cv::Vec3b>(y, x);
      if (p[0] < 60 && p[1] > 200 && p[2] > 200) {
        EXPECT_GE(x, ox + 2 * k - 3);
        EXPECT_LE(x, ox + 7 * k + 2);
        EXPECT_GE(y, oy + 2 * k - 3);
        EXPECT_LE(y, oy + 7 * k + 2);
      }
    }
  // Deterministic: a second run gives identical cluster colours.
  const fs::path dbg2 = dir / "dbg2";
  ASSERT_EQ(run("detect --profile paper --family 25h9 " + q(dir / "in.png") + " --debug-dir " + q(dbg2)).code, 0);
  EXPECT_EQ(slurp(dbg / "in_clusters.png"), slurp(dbg2 / "in_clusters.png"));
}

TEST(CliDetect, ProfilesAreNamedAndTheDefaultHasNoGradientPictures) {
  const fs::path dir = fresh("profiles");
  write_png(dir / "in.png", padded(rendered_tag(9, 12), 50, 40, 240, 200));
  const fs::path dbg = dir / "dbg";
  const Result r = run("detect --family 25h9 " + q(dir / "in.png") + " --debug-dir " + q(dbg));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = parse_json(r.out);
  EXPECT_EQ(doc["options"]["profile"].str, "default");
  ASSERT_EQ(doc["images"][0]["detections"].size(), 1u);
  EXPECT_TRUE(fs::exists(dbg / "in_quads.png"));
  EXPECT_TRUE(fs::exists(dbg / "in_samples.png"));
  EXPECT_FALSE(fs::exists(dbg / "in_clusters.png"));
  // The threshold finder's own stages: its pixel classes and boundary groups. The tag (k = 12 px a
  // cell at (50, 40)): white ring x in [50, 62), black ring [62, 74); next to the step each side is
  // classed, inside a wide flat band (2 px tiles: a 6 px window) and on the flat canvas unknown.
  const cv::Mat classes = cv::imread((dbg / "in_threshold.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(classes.type(), CV_8UC1);
  ASSERT_EQ(classes.cols, 240);
  ASSERT_EQ(classes.rows, 200);
  for (int y = 0; y < classes.rows; ++y)
    for (int x = 0; x < classes.cols; ++x) {
      const int v = classes.at<std::uint8_t>(y, x);
      ASSERT_TRUE(v == 0 || v == 127 || v == 255) << x << "," << y << ": " << v;
    }
  EXPECT_EQ(classes.at<std::uint8_t>(94, 61), 255);  // white ring
  EXPECT_EQ(classes.at<std::uint8_t>(94, 62), 0);    // black ring
  EXPECT_EQ(classes.at<std::uint8_t>(94, 68), 127);  // the black ring's flat middle
  EXPECT_EQ(classes.at<std::uint8_t>(5, 5), 127);    // flat canvas
  const cv::Mat groups = cv::imread((dbg / "in_boundaries.png").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(groups.cols, 240);
  const auto coloured = [&](int x, int y) {
    const cv::Vec3b c = groups.at<cv::Vec3b>(y, x);
    return !(c[0] == c[1] && c[1] == c[2]);
  };
  EXPECT_TRUE(coloured(62, 94));   // the black ring's outer edge (its dark side) belongs to a group
  EXPECT_FALSE(coloured(68, 94));  // inside the ring: no boundary
  EXPECT_FALSE(coloured(5, 5));
  // At half resolution both are at the threshold's (half) resolution.
  const fs::path dbg_half = dir / "dbg_half";
  ASSERT_EQ(run("detect --family 25h9 --half-res " + q(dir / "in.png") + " --debug-dir " + q(dbg_half)).code, 0);
  const cv::Mat half_classes = cv::imread((dbg_half / "in_threshold.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(half_classes.cols, 120);
  EXPECT_EQ(half_classes.rows, 100);
  EXPECT_EQ(cv::imread((dbg_half / "in_boundaries.png").string(), cv::IMREAD_COLOR).cols, 120);
  const Result p = run("detect --profile paper --family 25h9 " + q(dir / "in.png"));
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_EQ(parse_json(p.out)["options"]["profile"].str, "paper");
  const Result t = run("detect --profile thorough --family 25h9 " + q(dir / "in.png"));
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_EQ(parse_json(t.out)["options"]["profile"].str, "thorough");
  EXPECT_EQ(parse_json(run("detect --family 25h9 " + q(dir / "in.png")).out)["options"]["profile"].str, "default");
  const Result bad = run("detect --profile fast " + q(dir / "in.png"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--profile fast: expected default, thorough or paper"), std::string::npos) << bad.err;
}

TEST(CliDetect, VideoFramesAreEachAResult) {
  const fs::path dir = fresh("video");
  constexpr int k = 12;
  const fs::path video = dir / "clip.avi";
  {
    cv::VideoWriter w(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, cv::Size(240, 200), true);
    if (!w.isOpened()) GTEST_SKIP() << "no MJPG video writer in this OpenCV";
    for (int f = 0; f < 3; ++f) {
      cv::Mat bgr;
      cv::cvtColor(padded(rendered_tag(4, k), 30 + 20 * f, 40, 240, 200), bgr, cv::COLOR_GRAY2BGR);
      w.write(bgr);
    }
  }
  const fs::path drawn = dir / "drawn";
  const Result r = run("detect --family 25h9 " + q(video) + " --draw " + q(drawn));
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = parse_json(r.out);
  ASSERT_EQ(j["images"].size(), 3u);
  for (std::size_t f = 0; f < 3; ++f) {
    const Json& img = j["images"][f];
    EXPECT_EQ(img["input"].str, video.string() + "#frame" + std::to_string(f));
    EXPECT_EQ(img["frame"].num, static_cast<double>(f));
    EXPECT_EQ(img["width"].num, 240);
    ASSERT_EQ(img["detections"].size(), 1u);
    EXPECT_EQ(img["detections"][0]["id"].num, 4);
    // JPEG-compressed frames: corners within a pixel of where the tag was pasted.
    expect_corners(img["detections"][0], upright_corners(30 + 20 * static_cast<int>(f), 40, k), 1.0);
    EXPECT_TRUE(fs::exists(drawn / ("clip_frame" + std::to_string(f) + ".png")));
  }
}

TEST(CliDetect, AVideoFrameThatCannotBeDecodedIsAnErrorNotTheEnd) {
  const fs::path dir = fresh("video_bad_frame");
  const fs::path video = dir / "clip.avi";
  {
    cv::VideoWriter w(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, cv::Size(240, 200), true);
    if (!w.isOpened()) GTEST_SKIP() << "no MJPG video writer in this OpenCV";
    for (int f = 0; f < 4; ++f) {
      cv::Mat bgr;
      cv::cvtColor(padded(rendered_tag(4, 12), 30 + 20 * f, 40, 240, 200), bgr, cv::COLOR_GRAY2BGR);
      w.write(bgr);
    }
  }
  // The second frame's JPEG headers overwritten: the reader stops there, though 4 frames are declared.
  std::string bytes = slurp(video);
  const std::string soi = "\xFF\xD8\xFF";
  const std::size_t second = bytes.find(soi, bytes.find(soi) + 1);
  ASSERT_NE(second, std::string::npos);
  for (std::size_t i = second + 2; i < std::min(bytes.size(), second + 600); ++i) bytes[i] = 'x';
  std::ofstream(video, std::ios::binary) << bytes;
  const Result r = run("detect --family 25h9 --format jsonl " + q(video));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("clip.avi#frame1: cannot decode frame 1 of the 4 the video declares"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("#frame0"), std::string::npos) << r.out;
}

TEST(CliDetect, StoppedBySigtermTheDocumentIsStillWhole) {
  const fs::path dir = fresh("interrupted");
  const fs::path img = dir / "frame.png";
  cv::Mat big(600, 800, CV_8UC1);
  cv::randu(big, 0, 255);  // texture: each image takes the detector some milliseconds
  cv::GaussianBlur(big, big, cv::Size(0, 0), 1.5);
  padded(rendered_tag(4, 12), 0, 0, 240, 200).copyTo(big(cv::Rect(100, 100, 240, 200)));
  write_png(img, big);
  std::string args = "detect --family 25h9 --threads 1";
  for (int i = 0; i < 2000; ++i) args += " " + q(img);
  const pid_t pid = tagbench::testing::start_tagbench(args, dir);
  // Once some images are out (the document has begun and is mid-way), SIGTERM.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (slurp(dir / "stdout").find("\"detections\"") == std::string::npos && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(pid, SIGTERM);
  const Result r = tagbench::testing::wait_tagbench(pid, dir);
  ASSERT_EQ(r.code, 128 + SIGTERM) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  const Json j = parse_json(r.out);  // closed: it parses
  EXPECT_GE(j["images"].size(), 1u);
  EXPECT_LT(j["images"].size(), 2000u);
  ASSERT_EQ(j["errors"].size(), 1u);
  EXPECT_EQ(j["errors"][0]["input"].str, "(interrupted)");
  EXPECT_EQ(j["errors"][0]["error"].str.rfind("SIGTERM: stopped", 0), 0u);
}

TEST(CliDetect, TinyImagesAndNamesThatNeedEscaping) {
  const fs::path dir = fresh("tiny");
  const fs::path one = dir / "one.png";
  write_png(one, cv::Mat(1, 1, CV_8UC1, cv::Scalar(200)));
  const fs::path odd = dir / "we\"ird\\name,1.png";
  write_png(odd, padded(rendered_tag(6, 12), 10, 10, 130, 130));
  const Result r = run("detect --family 25h9 " + q(one) + " " + q(odd));
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = parse_json(r.out);  // throws on invalid JSON
  ASSERT_EQ(j["images"].size(), 2u);
  EXPECT_EQ(j["images"][0]["width"].num, 1);
  EXPECT_EQ(j["images"][0]["detections"].size(), 0u) << "a 1-pixel image is valid and has no tags";
  EXPECT_EQ(j["images"][1]["input"].str, odd.string());
  EXPECT_EQ(j["images"][1]["detections"][0]["id"].num, 6);
  const Result c = run("detect --family 25h9 --format csv " + q(odd));
  const auto rows = parse_csv(c.out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("input"), odd.string());
}

TEST(CliDetect, BadInputsAndOptionsAreRefusedOnOneLine) {
  const fs::path dir = fresh("bad");
  const fs::path good = dir / "good.png", draw = dir / "drawn.png", dbg = dir / "dbg";
  write_png(good, padded(rendered_tag(8, 12), 20, 20, 150, 150));
  const std::string outputs = " --draw " + q(draw) + " --debug-dir " + q(dbg);
  const auto refused = [&](const std::string& args, const std::string& fragment, int code) {
    const Result r = run("detect " + args + outputs);
    EXPECT_EQ(r.code, code) << args;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << args << "\nstderr: " << r.err;
    EXPECT_EQ(lines(r.err), 1) << "one line: " << r.err;
    EXPECT_FALSE(fs::exists(draw)) << args;
    EXPECT_FALSE(fs::exists(dbg)) << args;
    return r;
  };
  const std::string g = " --family 25h9 " + q(good);
  refused("--max-hamming -1" + g, "--max-hamming: -1 is outside 0..16", 2);
  refused("--camera 1,2,3 --tag-size 0.1" + g, "--camera 1,2,3: expected fx,fy,cx,cy, got 3 numbers", 2);
  refused("--camera nan,400,200,200 --tag-size 0.1" + g, "'nan' is not a finite number", 2);
  refused("--camera 400,-400,200,200 --tag-size 0.1" + g, "fx and fy must be > 0", 2);
  refused("--camera 400,400,200,200 --tag-size 0" + g, "--tag-size 0: the tag size must be > 0", 2);
  refused("--tag-size 0" + g, "the tag size must be > 0", 2);
  refused("--tag-size 0.1" + g, "--tag-size needs --camera", 2);
  refused("--camera 400,400,200,200" + g, "--camera needs --tag-size", 2);
  refused("--distortion 0.1,0,0,0,0" + g, "--distortion needs --camera", 2);
  refused("--format xml" + g, "--format xml", 2);
  refused("--threads 0" + g, "--threads", 2);
  refused("--bogus" + g, "unknown option '--bogus'", 2);
  refused("--family 36h99 " + q(good), "unknown family '36h99'", 2);
  refused("--max-hamming 9" + g, "--max-hamming = 9: must be in 0..8 (below the minimum Hamming distance 9 of family 25h9)", 2);
  refused("--camera 400,400,200,200 --tag-size 1e300" + g, "--tag-size = 1e+300: must be in [1e-06, 1e+06]", 2);
  refused("--camera 1e-300,400,200,200 --tag-size 0.1" + g, "--camera fx = 1e-300: must be in [0.01, 1e+08]", 2);
  refused("--family \"$(printf '36h\\n99')\" " + q(good), "unknown family '36h\\x0a99'", 2);  // one line, the newline shown
  refused("--family 25h9", "no input", 2);
  // Input errors: the input named, JSON still printed, exit 1, nothing drawn for it.
  const Result missing = refused("--family 25h9 " + q(dir / "missing.png"), (dir / "missing.png").string() + ": no such file", 1);
  EXPECT_EQ(parse_json(missing.out)["errors"][0]["input"].str, (dir / "missing.png").string());
  std::ofstream(dir / "empty.png").close();
  refused("--family 25h9 " + q(dir / "empty.png"), "empty.png: empty file (0 bytes)", 1);
  fs::create_directories(dir / "noimages");
  refused("--family 25h9 " + q(dir / "noimages"), "no image files", 1);
  std::ofstream(dir / "broken.avi") << "not a video";
  refused("--family 25h9 " + q(dir / "broken.avi"), "broken.avi", 1);
  // A truncated PNG is corrupt.
  const std::string png = slurp(good);
  std::ofstream(dir / "truncated.png", std::ios::binary) << png.substr(0, png.size() / 2);
  refused("--family 25h9 " + q(dir / "truncated.png"), "truncated.png", 1);

  // A bad input among good ones: the good one is still reported.
  const Result mixed = run("detect --family 25h9 " + q(dir / "missing.png") + " " + q(good));
  EXPECT_EQ(mixed.code, 1);
  EXPECT_EQ(lines(mixed.err), 1) << mixed.err;
  const Json j = parse_json(mixed.out);
  ASSERT_EQ(j["images"].size(), 1u);
  EXPECT_EQ(j["images"][0]["detections"][0]["id"].num, 8);
}

}  // namespace test_cli_detect
