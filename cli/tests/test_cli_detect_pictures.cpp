// `tagbench detect` end to end, the pictures it writes: --draw (the outline and the corner dot, JPEG
// output), --debug-dir (the six stages of the paper profile, at full and half resolution, and the
// threshold stages of the default profile), and the named profiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_detect_util.hpp"

namespace test_cli_detect {

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

}  // namespace test_cli_detect
