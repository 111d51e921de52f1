// `tagbench detect` end to end, what it reads: colour, 16-bit and JPEG images, batches (directories,
// a corrupt file among good ones, input order with several threads), videos (and a frame that cannot
// be decoded), a long run stopped by SIGTERM, and the bad-input rules.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/types.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "cli_detect_util.hpp"
#include "kill_run.hpp"

namespace test_cli_detect {

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
