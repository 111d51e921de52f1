// POV-Ray renders that go wrong (issue 4, section 1): bad frames and templates are refused, a missing
// povray is one line naming the package, a frame that fails among good ones is reported and the
// others go on, and a broken template stops after three identical failures.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "raytrace/render.hpp"
#include "scratch_dir.hpp"
#include "test_frames.hpp"

namespace test_render_failures {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::bench;
using tagbench::bench::test::files_in;
using tagbench::bench::test::gentle_options;
using tagbench::bench::test::max_corner_error;
using tagbench::bench::test::plain_frames;

TEST(RaytraceRender, BadFramesAndTemplatesAreRefused) {
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_bad");
  const fs::path& dir = scratch.path();
  RenderOptions o = gentle_options(dir);
  FramePose f = plain_frames()[0];
  const std::string& plain = scene_template(SceneKind::kPlain);
  const auto refused = [&](const FramePose& frame, const std::string& tmpl, const std::string& fragment) {
    try {
      render_frames({plain_frames()[1], frame}, tmpl, o);
      ADD_FAILURE() << "not refused: " << fragment;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  FramePose g = f;
  g.tag_size = 0;
  refused(g, plain, "frame 1: tag size must be > 0");
  g = f;
  g.id = 587;
  refused(g, plain, "frame 1: id 587 is out of range");
  g = f;
  g.family = "99h99";
  refused(g, plain, "unknown family '99h99'");
  g = f;
  g.pose.t.z() = -1;
  refused(g, plain, "not in front of the camera");
  g = f;
  g.pose.R(0, 0) = 2;
  refused(g, plain, "R is not a rotation");
  refused(f, "camera {}", "exactly once");
  EXPECT_TRUE(files_in(dir).empty()) << "nothing written for refused input";
}

TEST(RaytraceRender, MissingPovrayIsOneLineNamingThePackage) {
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_nopovray");
  const fs::path& dir = scratch.path();
  FramePose f = plain_frames()[0];
  f.pose.t *= 1.2345;  // a frame in no cache
  RenderOptions o = gentle_options(dir);
  const std::string expected = "povray not found: install the Debian package povray";
  // A path or a name other than the default: the message names it.
  const fs::path not_executable = dir / "not-executable";
  { std::ofstream(not_executable) << "#!/bin/sh\n"; }
  for (const auto& [given, why] : std::vector<std::pair<std::string, std::string>>{
           {(dir / "no-such-povray").string(), "not an executable file"},
           {not_executable.string(), "not an executable file"},
           {"no-such-povray-name", "no executable of this name in PATH"}}) {
    o.povray = given;
    try {
      render_frames({f}, scene_template(SceneKind::kPlain), o);
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "povray '" + given + "': " + why);
    }
  }
  fs::remove(not_executable);
  // Through PATH: an empty directory holds no povray.
  const tagbench::testing::ScratchDir empty_scratch("tagbench_raytrace_emptypath");
  const fs::path& empty = empty_scratch.path();
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", empty.c_str(), 1);
  o.povray = "povray";
  EXPECT_FALSE(find_povray().has_value());
  try {
    render_frames({f}, scene_template(SceneKind::kPlain), o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_TRUE(files_in(dir).empty()) << "nothing written when povray is missing";
}

// The first of ten frames fails (POV-Ray stops at it); the other nine are rendered by a second run.
// Ten frames also take POV-Ray's two-digit frame numbers in the output names.
TEST(RaytraceRender, AFrameThatFailsIsReportedAndTheOthersGoOn) {
  REQUIRE_POVRAY();
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_failing");
  const fs::path& dir = scratch.path();
  std::vector<FramePose> frames(10, plain_frames()[0]);
  frames[0].extra_sdl = "#error \"deliberately broken frame\"";
  for (std::size_t i = 1; i < frames.size(); ++i) frames[i].pose.t *= 1.0 + 0.03 * static_cast<double>(i);
  const RenderReport r = render_frames(frames, scene_template(SceneKind::kPlain), gentle_options(dir));
  EXPECT_EQ(r.failed, 1u);
  EXPECT_EQ(r.rendered, 9u);
  EXPECT_EQ(r.povray_runs, 2);
  EXPECT_FALSE(r.frames[0].ok());
  EXPECT_TRUE(r.frames[0].png.empty());
  EXPECT_NE(r.frames[0].error.find("deliberately broken frame"), std::string::npos) << r.frames[0].error;
  EXPECT_EQ(r.frames[0].error.find('\n'), std::string::npos) << "one line";
  std::printf("the failed frame: %s\n", r.frames[0].error.c_str());
  const FramePose& last = frames.back();
  for (std::size_t i = 1; i < frames.size(); ++i) {
    ASSERT_TRUE(r.frames[i].ok()) << r.frames[i].error;
    EXPECT_EQ(r.frames[i].png.filename().string(), "frame-" + frame_cache_key(frames[i], scene_template(SceneKind::kPlain)) + ".png");
  }
  // Each file holds its own frame: the last one's tag is the smallest (the farthest).
  const cv::Mat img = read_frame_gray(r.frames.back().png);
  DetectorOptions opt = DetectorOptions::paper();
  const auto dets = detect(Detector(opt), img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_LT(max_corner_error(dets[0].corners, ground_truth(last).corners), 0.3);
}

TEST(RaytraceRender, ABrokenTemplateStopsAfterThreeIdenticalFailures) {
  REQUIRE_POVRAY();
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_broken");
  const fs::path& dir = scratch.path();
  std::vector<FramePose> frames(6, plain_frames()[0]);
  for (std::size_t i = 0; i < frames.size(); ++i) frames[i].pose.t *= 1.0 + 0.01 * static_cast<double>(i);
  const std::string broken = scene_template(SceneKind::kPlain) + "\nsphere { <0, 0, 0> undefined_thing }\n";
  const RenderReport r = render_frames(frames, broken, gentle_options(dir));
  EXPECT_EQ(r.failed, 6u);
  EXPECT_EQ(r.rendered, 0u);
  EXPECT_EQ(r.povray_runs, 3) << "not one run per frame";
  for (const auto& f : r.frames) {
    EXPECT_FALSE(f.ok());
    EXPECT_NE(f.error.find("Parse Error"), std::string::npos) << f.error;
  }
}

}  // namespace test_render_failures
