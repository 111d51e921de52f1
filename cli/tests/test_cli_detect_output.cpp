// `tagbench detect` end to end, what it prints: JSON and CSV output (checked against tags placed at
// known pixel positions and at a known pose), JSON lines, the pose axes in --draw's picture, the
// help, and input names that need escaping in JSON and CSV.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_detect_util.hpp"

namespace test_cli_detect {

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

}  // namespace test_cli_detect
