// tagbench detect --explain X,Y[,FAMILY:ID] (issue 17, section 2): why no tag was reported at a pixel.
// Synthetic images (detect/tests/synthetic_tag.hpp): a clean 36h11 tag is "detected" at its centre,
// and with another FAMILY:ID a wrong_id with the bits of that code read wrong; the same tag with two
// payload cells flipped, at --max-hamming 0, is a misread (2 bits wrong given its FAMILY:ID); a flat
// image has no_cluster; CSV puts the explanations on stderr; bad points are usage errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/tests/synthetic_tag.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_explain {

namespace fs = std::filesystem;
using namespace tagbench;

namespace {

const tagbench::testing::ScratchDir& scratch() {
  static const tagbench::testing::ScratchDir d("tagbench_cli_explain");
  return d;
}

tagbench::testing::CommandResult run(const std::string& args) { return tagbench::testing::run_tagbench("detect " + args, scratch().path()); }

// A 36h11 tag (id 7) centred at (150, 120), 90 px black square; `flips` payload cells inverted.
fs::path tag_image(const std::string& name, int flips) {
  TagCells cells = tag_cells(builtin_family("36h11"), 7);
  for (int k = 0; k < flips; ++k) {
    const int y = 2 + k, x = 2 + 2 * k;  // payload cells (the payload starts at cell 2)
    auto& c = cells.white[static_cast<std::size_t>(y * cells.n + x)];
    c = c ? 0 : 1;
  }
  const ImageF img = synth::render_tag(300, 240, cells, synth::homography_for(synth::square_tag_corners(150, 120, 90, 0.2)),
                                       0.6f, 4);
  cv::Mat m(img.height, img.width, CV_8UC1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) m.at<uchar>(y, x) = cv::saturate_cast<uchar>(img.at(x, y) * 255.0f + 0.5f);
  const fs::path p = scratch() / name;
  cv::imwrite(p.string(), m);
  return p;
}

// The value of "key": in the first explanation object after `from`.
std::string field(const std::string& json, const std::string& key, std::size_t from = 0) {
  const auto k = json.find("\"" + key + "\": ", from);
  if (k == std::string::npos) return "<none>";
  const auto v = k + key.size() + 4;
  const auto end = json.find_first_of(",}", json[v] == '"' ? json.find('"', v + 1) : v);
  std::string s = json.substr(v, end - v);
  if (!s.empty() && s.front() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

}  // namespace

TEST(CliExplain, ADetectedTagAndAnotherIdThere) {
  const fs::path img = tag_image("clean.png", 0);
  const auto r = run(img.string() + " --explain 150,120 --explain 150,120,36h11:8");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto first = r.out.find("\"explain\": [");
  ASSERT_NE(first, std::string::npos) << r.out;
  EXPECT_EQ(field(r.out, "stage", first), "detected");
  EXPECT_EQ(field(r.out, "text", first), "detected: 36h11 id 7");
  const auto second = r.out.find("\"given\": \"150,120,36h11:8\"");
  ASSERT_NE(second, std::string::npos) << r.out;
  EXPECT_EQ(field(r.out, "stage", second), "wrong_id");
  const auto& fam = builtin_family("36h11");
  int expect = 64;
  for (int rot = 0; rot < 4; ++rot)
    expect = std::min(expect, hamming(fam.codes()[7], rotate(fam.codes()[8], 6, rot)));
  EXPECT_EQ(field(r.out, "bits_wrong", second), std::to_string(expect));
  // JSON lines carry the same list, one line per image.
  const auto lines = run(img.string() + " --format jsonl --explain 150,120");
  ASSERT_EQ(lines.code, 0) << lines.err;
  EXPECT_EQ(std::count(lines.out.begin(), lines.out.end(), '\n'), 1) << lines.out;
  const auto in_line = lines.out.find("\"explain\": [");
  ASSERT_NE(in_line, std::string::npos) << lines.out;
  EXPECT_EQ(field(lines.out, "stage", in_line), "detected");
  // Without --explain the output has no "explain" key.
  const auto plain = run(img.string());
  ASSERT_EQ(plain.code, 0);
  EXPECT_EQ(plain.out.find("\"explain\""), std::string::npos);
}

TEST(CliExplain, FlippedCellsAreAMisreadWithTheirCount) {
  const fs::path img = tag_image("flipped.png", 2);
  const auto r = run(img.string() + " --max-hamming 0 --explain 150,120 --explain 150,120,36h11:7");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"detections\": []"), std::string::npos) << r.out;
  const auto first = r.out.find("\"explain\": [");
  ASSERT_NE(first, std::string::npos) << r.out;
  EXPECT_EQ(field(r.out, "stage", first), "misread");
  EXPECT_EQ(field(r.out, "bits_wrong", first), "null");
  const auto second = r.out.find("\"given\": \"150,120,36h11:7\"");
  EXPECT_EQ(field(r.out, "stage", second), "misread");
  EXPECT_EQ(field(r.out, "bits_wrong", second), "2");
  // At --max-hamming 2 it is read: detected.
  const auto ok = run(img.string() + " --max-hamming 2 --explain 150,120,36h11:7");
  EXPECT_EQ(field(ok.out, "stage", ok.out.find("\"explain\"")), "detected");
}

TEST(CliExplain, AFlatImageHasNoQuadOrNoClusterByProfileAndCsvSaysItOnStderr) {
  const fs::path img = scratch() / "flat.png";
  cv::imwrite(img.string(), cv::Mat(100, 120, CV_8UC1, cv::Scalar(128)));
  // The default profile's threshold quad finder has no gradient clusters or segments: no_quad.
  const auto r = run(img.string() + " --format csv --explain 60,50");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("\"explain\""), std::string::npos) << r.out;
  EXPECT_EQ(r.err, "tagbench detect: " + img.string() +
                       ": explain 60,50: no_quad: no candidate quad holds the point: no outline of a dark square there "
                       "in the adaptive threshold's classes; within 10 px: 0 % of the pixels dark, 0 % light, 100 % "
                       "too flat to class, no boundary group\n");
  // The paper's gradient pipeline says how far it got.
  const auto paper = run(img.string() + " --profile paper --format csv --explain 60,50");
  ASSERT_EQ(paper.code, 0) << paper.err;
  EXPECT_EQ(paper.err, "tagbench detect: " + img.string() + ": explain 60,50: no_cluster: no gradient cluster within 50 px\n");
}

TEST(CliExplain, TheThresholdFindersNoQuadNamesTheClassesAndGroupsNearThePoint) {
  // On grey: a dark 6 x 5 px block (30 px: a component, one boundary group, too small for a quad)
  // and a dark 4 x 4 px speck (16 px: under the 25 px a component needs, so no group).
  const fs::path img = scratch() / "blocks.png";
  cv::Mat m(100, 120, CV_8UC1, cv::Scalar(160));
  m(cv::Rect(30, 40, 6, 5)).setTo(40);
  m(cv::Rect(80, 40, 4, 4)).setTo(40);
  cv::imwrite(img.string(), m);
  const auto r = run(img.string() + " --format csv --explain 33,42 --explain 82,42 --explain 60,80");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto line = [&](const std::string& at) {
    const auto i = r.err.find("explain " + at + ": no_quad: ");
    return i == std::string::npos ? std::string() : r.err.substr(i, r.err.find('\n', i) - i);
  };
  const std::string block = line("33,42"), speck = line("82,42"), flat = line("60,80");
  EXPECT_NE(block.find(", 1 boundary group (the largest 6 x 5 px; 1 with enough points for the quad fit)"), std::string::npos)
      << r.err;
  EXPECT_EQ(block.find(" 0 % of the pixels dark"), std::string::npos) << block;
  EXPECT_NE(speck.find("too flat to class, no boundary group"), std::string::npos) << r.err;
  EXPECT_EQ(speck.find(" 0 % of the pixels dark"), std::string::npos) << speck;  // classed, but no component
  EXPECT_NE(flat.find("0 % of the pixels dark, 0 % light, 100 % too flat to class, no boundary group"), std::string::npos)
      << r.err;
}

TEST(CliExplain, BadPointsAreUsageErrors) {
  const fs::path img = tag_image("bad.png", 0);
  for (const std::string bad :
       {"1", "1,2,3,4", "x,2", "1,2,36h11", "1,2,36h11:587", "1,2,nofamily:1", "1,2,36h11:-1", "1,2,16h5:3"}) {
    const auto r = run(img.string() + " --explain " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_EQ(r.err.rfind("tagbench detect: --explain " + bad + ": ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << bad;
  }
  // A point off the image is said to be, not explained as a place without quads.
  const auto off = run(img.string() + " --explain -3,50 --explain 50,1e6");
  ASSERT_EQ(off.code, 0) << off.err;
  for (std::size_t at = off.out.find("\"stage\""), n = 0; n < 2; ++n, at = off.out.find("\"stage\"", at + 1)) {
    ASSERT_NE(at, std::string::npos) << off.out;
    EXPECT_EQ(field(off.out, "stage", at), "outside_image");
  }
}

}  // namespace test_cli_explain
