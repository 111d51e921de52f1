// The POV-Ray frame cache (issue 4, section 1): the key changes with everything that changes the
// pixels, a rerun renders nothing, lost or damaged frames are rendered again, and a killed run's
// finished frames are kept while its other files are removed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "raytrace/render.hpp"
#include "tools/atomic_file.hpp"
#include "scratch_dir.hpp"
#include "test_frames.hpp"

namespace test_render_cache {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::bench;
using tagbench::bench::test::files_in;
using tagbench::bench::test::gentle_options;
using tagbench::bench::test::plain_frames;

namespace {

// Two frames of ids `id` and `id` + 1 at `distance` m and `phi` degrees, tilted about axes 90 degrees apart.
std::pair<FramePose, FramePose> two_frames(int id, double distance, double phi) {
  FramePose a, b;
  a.id = id;
  a.pose = view_pose({.distance = distance, .phi_deg = phi, .tilt_axis_deg = 0});
  b.id = id + 1;
  b.pose = view_pose({.distance = distance, .phi_deg = phi, .tilt_axis_deg = 90});
  return {a, b};
}

}  // namespace

TEST(RaytraceCache, KeyChangesWithEverythingThatChangesThePixels) {
  const std::string& plain = scene_template(SceneKind::kPlain);
  const FramePose base = plain_frames()[0];
  const std::string k = frame_cache_key(base, plain);
  EXPECT_EQ(k.size(), 16u);
  EXPECT_EQ(frame_cache_key(base, plain), k);  // deterministic
  std::set<std::string> keys{k};
  FramePose f = base;
  f.id = 1;
  keys.insert(frame_cache_key(f, plain));
  f = base;
  f.family = "25h9";
  keys.insert(frame_cache_key(f, plain));
  f = base;
  f.tag_size *= 1.0000001;
  keys.insert(frame_cache_key(f, plain));
  f = base;
  f.pose.t.x() += 1e-9;
  keys.insert(frame_cache_key(f, plain));
  f = base;
  f.pose.R = base.pose.R * Eigen::AngleAxisd(1e-7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  keys.insert(frame_cache_key(f, plain));
  f = base;
  f.extra_sdl = "box { <0,0,0>, <1,1,1> }";
  keys.insert(frame_cache_key(f, plain));
  keys.insert(frame_cache_key(base, scene_template(SceneKind::kRealistic)));
  EXPECT_EQ(keys.size(), 8u) << "every change gives its own key";
}

TEST(RaytraceCache, RerunRendersNothingAndLostOrDamagedFramesAreRenderedAgain) {
  REQUIRE_POVRAY();
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_cache");
  const fs::path& dir = scratch.path();
  const auto [a, b] = two_frames(3, 1.5, 20);
  RenderOptions o = gentle_options(dir);
  o.processes = 2;  // two frames: two povray runs at once, frames 1 and 2 of one animation (+SF/+EF)
  std::vector<std::pair<std::size_t, std::size_t>> progress;
  o.progress = [&](std::size_t done, std::size_t total) { progress.emplace_back(done, total); };
  const std::string& plain = scene_template(SceneKind::kPlain);
  const RenderReport first = render_frames({a, b, a}, plain, o);
  EXPECT_EQ(first.rendered, 2u);  // the duplicate renders once
  EXPECT_EQ(first.from_cache, 0u);
  EXPECT_EQ(first.povray_runs, 2);
  for (const auto& f : first.frames) ASSERT_TRUE(f.ok()) << f.error;
  EXPECT_EQ(first.frames[0].png, first.frames[2].png);
  EXPECT_NE(first.frames[0].png, first.frames[1].png);
  EXPECT_EQ(first.frames[0].png.filename().string(), "frame-" + frame_cache_key(a, plain) + ".png");
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), std::make_pair(std::size_t{2}, std::size_t{2}));
  // Only frames and tag images are left: no scene, log or temporary.
  for (const auto& name : files_in(dir))
    EXPECT_TRUE(name.rfind("frame-", 0) == 0 || name.rfind("tag-", 0) == 0) << name;
  const cv::Mat pa = read_frame_gray(first.frames[0].png), pb = read_frame_gray(first.frames[1].png);
  EXPECT_GT(cv::norm(pa, pb, cv::NORM_INF), 0) << "different poses, different pictures";
  const auto mtime = fs::last_write_time(first.frames[0].png);

  // A rerun renders nothing: it does not even need povray.
  RenderOptions no_povray = gentle_options(dir);
  no_povray.povray = (dir / "no-such-povray").string();
  const RenderReport second = render_frames({a, b}, plain, no_povray);
  EXPECT_EQ(second.rendered, 0u);
  EXPECT_EQ(second.from_cache, 2u);
  EXPECT_EQ(second.povray_runs, 0);
  EXPECT_TRUE(second.frames[0].from_cache && second.frames[1].from_cache);
  EXPECT_EQ(fs::last_write_time(second.frames[0].png), mtime);
  EXPECT_EQ(cv::norm(read_frame_gray(second.frames[0].png), pa, cv::NORM_INF), 0);

  // An interrupted run: one frame lost, the other half written. Both are rendered again, to the same
  // pixels, now in one povray run (frames rendered alone or within an animation are identical).
  fs::remove(first.frames[0].png);
  const std::string bytes = [&] {
    std::ifstream in(first.frames[1].png, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  std::ofstream(first.frames[1].png, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() / 2);
  const RenderReport third = render_frames({a, b}, plain, gentle_options(dir));
  EXPECT_EQ(third.rendered, 2u);
  EXPECT_EQ(third.from_cache, 0u);
  EXPECT_EQ(third.povray_runs, 1);
  ASSERT_TRUE(third.frames[0].ok() && third.frames[1].ok());
  EXPECT_EQ(cv::norm(read_frame_gray(third.frames[0].png), pa, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(read_frame_gray(third.frames[1].png), pb, cv::NORM_INF), 0);
}

// A run killed while POV-Ray rendered (Ctrl-C, kill -9) leaves its batch's files. The next run keeps
// the frames that batch finished (no povray needed for them), drops its half-written image, scene,
// key list and log, and leaves a live run's batch alone.
TEST(RaytraceCache, AKilledRunsFinishedFramesAreKeptAndItsOtherFilesRemoved) {
  const tagbench::testing::ScratchDir scratch("tagbench_raytrace_deadbatch");
  const fs::path& dir = scratch.path();
  const auto [a, b] = two_frames(5, 1.7, 10);
  const std::string& plain = scene_template(SceneKind::kPlain);
  const std::string ka = frame_cache_key(a, plain), kb = frame_cache_key(b, plain);
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string dead = tagbench::owner_tag(pid) + "-0123456789ab", alive = tagbench::owner_tag() + "-ba9876543210";
  cv::Mat frame(kRenderHeight, kRenderWidth, CV_8UC1, cv::Scalar(77));
  ASSERT_TRUE(cv::imwrite((dir / ("tmp-" + dead + "-1.png")).string(), frame));
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", frame, png));
  { std::ofstream(dir / ("tmp-" + dead + "-2.png"), std::ios::binary).write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size() / 2)); }
  { std::ofstream(dir / ("batch-" + dead + ".keys")) << ka << "\n" << kb << "\n"; }
  { std::ofstream(dir / ("batch-" + dead + ".pov")) << "scene"; }
  { std::ofstream(dir / ("batch-" + dead + "-w0-0.log")) << "log"; }
  { std::ofstream(dir / ("batch-" + alive + ".pov")) << "scene"; }
  ASSERT_TRUE(cv::imwrite((dir / ("tmp-" + alive + "-1.png")).string(), frame));

  RenderOptions o = gentle_options(dir);
  o.povray = (dir / "no-such-povray").string();
  const RenderReport r = render_frames({a}, plain, o);  // frame a: kept from the dead batch, no povray
  EXPECT_EQ(r.from_cache, 1u);
  EXPECT_EQ(r.rendered, 0u);
  ASSERT_TRUE(r.frames[0].ok()) << r.frames[0].error;
  EXPECT_EQ(cv::norm(read_frame_gray(r.frames[0].png), frame, cv::NORM_INF), 0);
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"frame-" + ka + ".png", "batch-" + alive + ".pov",
                                                   "tmp-" + alive + "-1.png"}));
  // Frame b's image was half written: it is rendered (here: refused, as there is no povray).
  EXPECT_THROW(render_frames({b}, plain, o), std::runtime_error);
}

}  // namespace test_render_cache
