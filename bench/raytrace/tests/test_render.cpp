// POV-Ray frames and their ground truth (issue 4, section 1): the scene conventions proved by our
// detector finding the rendered corners where the ground truth puts them, the plain and realistic
// scenes, the frame cache (a rerun renders nothing, lost or damaged frames are rendered again), a
// frame that fails among good ones, and a missing povray.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "raytrace/render.hpp"
#include "tools/atomic_file.hpp"
#include "test_frames.hpp"

namespace test_render {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::bench;
using tagbench::bench::test::gentle_options;
using tagbench::bench::test::have_povray;
using tagbench::bench::test::plain_frames;
using tagbench::bench::test::scratch_dir;
using tagbench::bench::test::shared_cache;

namespace {

// An empty directory of its own for one test, removed afterwards.
struct FreshDir {
  fs::path path;
  explicit FreshDir(const std::string& name)
      : path(scratch_dir("tagbench_raytrace_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~FreshDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  FreshDir(const FreshDir&) = delete;
  FreshDir& operator=(const FreshDir&) = delete;
};

double max_corner_error(const Corners& a, const Corners& b) {
  double m = 0;
  for (std::size_t k = 0; k < 4; ++k) m = std::max(m, (a[k] - b[k]).norm());
  return m;
}

// Pixels of `gray` outside the whole printed tag (its projected outline grown by `margin` px).
cv::Mat outside_tag_mask(const FramePose& f, double margin) {
  FramePose whole = f;
  whole.tag_size = f.tag_size * 10 / 8;  // 36h11: the printed tag is 10 cells, the black square 8
  const Corners c = ground_truth(whole).corners;
  std::vector<cv::Point> poly;
  const Eigen::Vector2d centre = (c[0] + c[1] + c[2] + c[3]) / 4;
  for (const auto& p : c) {
    const Eigen::Vector2d q = p + (p - centre).normalized() * margin;
    poly.emplace_back(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())));
  }
  cv::Mat mask(kRenderHeight, kRenderWidth, CV_8UC1, cv::Scalar(255));
  cv::fillConvexPoly(mask, poly, cv::Scalar(0));
  return mask;
}

// Two frames of ids `id` and `id` + 1 at `distance` m and `phi` degrees, tilted about axes 90 degrees apart.
std::pair<FramePose, FramePose> two_frames(int id, double distance, double phi) {
  FramePose a, b;
  a.id = id;
  a.pose = view_pose({.distance = distance, .phi_deg = phi, .tilt_axis_deg = 0});
  b.id = id + 1;
  b.pose = view_pose({.distance = distance, .phi_deg = phi, .tilt_axis_deg = 90});
  return {a, b};
}

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> s;
  for (const auto& e : fs::directory_iterator(dir)) s.insert(e.path().filename().string());
  return s;
}

}  // namespace

TEST(RaytraceGeometry, RenderCameraIsThePapersPinhole) {
  const CameraIntrinsics K = render_camera();
  EXPECT_EQ(K.fx, 400);
  EXPECT_EQ(K.fy, 400);
  EXPECT_EQ(K.cx, 199.5);  // the optical axis passes between pixels 199 and 200
  EXPECT_EQ(K.cy, 199.5);
}

TEST(RaytraceGeometry, ViewPoseHasTheRequestedDistanceAngleAndImagePoint) {
  const CameraIntrinsics K = render_camera();
  for (const double phi : {0.0, 30.0, 85.0}) {
    for (const double axis : {0.0, 70.0, 200.0}) {
      const ViewSpec v{.distance = 2.5, .phi_deg = phi, .tilt_axis_deg = axis, .roll_deg = 40, .pixel = {120.0, 260.0}};
      const Pose p = view_pose(v);
      EXPECT_NEAR((p.R.transpose() * p.R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
      EXPECT_NEAR(p.R.determinant(), 1, 1e-12);
      EXPECT_NEAR(p.t.norm(), 2.5, 1e-12);
      EXPECT_NEAR(K.fx * p.t.x() / p.t.z() + K.cx, 120, 1e-9);
      EXPECT_NEAR(K.fy * p.t.y() / p.t.z() + K.cy, 260, 1e-9);
      // The printed face's normal (-z of the tag) against the direction to the camera (-t).
      const Eigen::Vector3d normal = -p.R.col(2), to_camera = -p.t.normalized();
      EXPECT_NEAR(std::acos(std::clamp(normal.dot(to_camera), -1.0, 1.0)) * 180 / M_PI, phi, 1e-6);
    }
  }
  // Face-on at the image centre, roll 0: the tag's axes are the camera's; a roll turns the printed
  // top-left corner clockwise in the image (toward the top edge, then the right).
  const Pose p0 = view_pose({.distance = 1});
  EXPECT_NEAR((p0.R - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  FramePose f;
  f.tag_size = 0.2;
  f.pose = view_pose({.distance = 1, .roll_deg = 90});
  const Corners c = ground_truth(f).corners;
  EXPECT_NEAR(c[0].x(), 199.5 + 40, 1e-9);  // TL now at the top-right
  EXPECT_NEAR(c[0].y(), 199.5 - 40, 1e-9);
  EXPECT_THROW(view_pose({.distance = 0}), std::invalid_argument);
  EXPECT_THROW(view_pose({.distance = 1, .phi_deg = 90}), std::invalid_argument);
}

TEST(RaytraceGeometry, GroundTruthCornersAreTheProjectedBlackSquareInPrintedOrder) {
  FramePose f;
  f.tag_size = 0.2;
  f.pose.t = Eigen::Vector3d(0, 0, 1);  // face-on, 1 m: the black square is 400 * 0.2 = 80 px wide
  const GroundTruth g = ground_truth(f);
  EXPECT_NEAR(g.black_square_px, 80, 1e-9);
  const double lo = 199.5 - 40, hi = 199.5 + 40;
  EXPECT_TRUE(g.corners[0].isApprox(Eigen::Vector2d(lo, lo)));  // top-left
  EXPECT_TRUE(g.corners[1].isApprox(Eigen::Vector2d(hi, lo)));  // top-right
  EXPECT_TRUE(g.corners[2].isApprox(Eigen::Vector2d(hi, hi)));  // bottom-right
  EXPECT_TRUE(g.corners[3].isApprox(Eigen::Vector2d(lo, hi)));  // bottom-left
}

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

TEST(RaytraceRender, BadFramesAndTemplatesAreRefused) {
  const FreshDir scratch("bad");
  const fs::path& dir = scratch.path;
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
  const FreshDir scratch("nopovray");
  const fs::path& dir = scratch.path;
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
  const FreshDir empty_scratch("emptypath");
  const fs::path& empty = empty_scratch.path;
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

// The scene conventions (camera, S R S matrix, image_map orientation, principal point): our detector
// finds the rendered black square where the ground truth projects it, in printed order.
TEST(RaytraceRender, OurDetectorFindsThePlainFramesAtTheGroundTruth) {
  REQUIRE_POVRAY();
  const auto frames = plain_frames();
  const RenderReport r = render_frames(frames, scene_template(SceneKind::kPlain), gentle_options(shared_cache()));
  ASSERT_EQ(r.failed, 0u);
  DetectorOptions opt = DetectorOptions::paper();
  opt.camera = render_camera();
  opt.tag_size = frames[0].tag_size;
  const Detector detector(opt);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    ASSERT_TRUE(r.frames[i].ok()) << r.frames[i].error;
    const cv::Mat img = read_frame_gray(r.frames[i].png);
    ASSERT_EQ(img.cols, 400);
    ASSERT_EQ(img.rows, 400);
    const auto dets = detect(detector, img);
    ASSERT_EQ(dets.size(), 1u) << "frame " << i;
    const Detection& d = dets[0];
    EXPECT_EQ(d.id, frames[i].id);
    const GroundTruth g = ground_truth(frames[i]);
    const double corner = max_corner_error(d.corners, g.corners);
    ASSERT_TRUE(d.pose.has_value());
    const double orient = rotation_angle_deg(d.pose->pose.R, g.pose.R);
    const double dist = 100 * std::abs(d.pose->pose.t.norm() - g.pose.t.norm()) / g.pose.t.norm();
    std::printf("frame %zu (id %d, %.0f px): corner max %.3f px, orientation %.3f deg, distance %.3f %%\n", i,
                frames[i].id, g.black_square_px, corner, orient, dist);
    EXPECT_LT(corner, 0.3) << "frame " << i;
    EXPECT_LT(orient, 1.0) << "frame " << i;
    EXPECT_LT(dist, 1.0) << "frame " << i;
    // Plain scene: everything away from the tag is the uniform grey background.
    double lo = 0, hi = 0;
    cv::minMaxLoc(img, &lo, &hi, nullptr, nullptr, outside_tag_mask(frames[i], 3));
    EXPECT_EQ(lo, hi) << "frame " << i;
    EXPECT_NEAR(lo, 128, 1);  // rgb 0.5, linear output
  }
}

TEST(RaytraceRender, RealisticSceneShowsMoreThanTheTagAndTheTagIsFound) {
  REQUIRE_POVRAY();
  FramePose f;
  f.id = 42;
  f.pose = view_pose({.distance = 1.2, .phi_deg = 35, .tilt_axis_deg = 80, .roll_deg = 15, .pixel = {190.0, 170.0}});
  const RenderReport r = render_frames({f}, scene_template(SceneKind::kRealistic), gentle_options(shared_cache()));
  ASSERT_TRUE(r.frames[0].ok()) << r.frames[0].error;
  const cv::Mat img = read_frame_gray(r.frames[0].png);
  // The floor and wall are textured: well away from the tag the picture is anything but uniform.
  const cv::Mat outside = outside_tag_mask(f, 10);
  double lo = 0, hi = 0;
  cv::minMaxLoc(img, &lo, &hi, nullptr, nullptr, outside);
  EXPECT_GT(hi - lo, 60) << "textures and light in view";
  DetectorOptions opt = DetectorOptions::paper();
  opt.camera = render_camera();
  opt.tag_size = f.tag_size;
  const auto dets = detect(Detector(opt), img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 42);
  const GroundTruth g = ground_truth(f);
  const double corner = max_corner_error(dets[0].corners, g.corners);
  std::printf("realistic: corner max %.3f px, orientation %.3f deg\n", corner,
              rotation_angle_deg(dets[0].pose->pose.R, g.pose.R));
  EXPECT_LT(corner, 0.5);
}

TEST(RaytraceCache, RerunRendersNothingAndLostOrDamagedFramesAreRenderedAgain) {
  REQUIRE_POVRAY();
  const FreshDir scratch("cache");
  const fs::path& dir = scratch.path;
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
  const FreshDir scratch("deadbatch");
  const fs::path& dir = scratch.path;
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

// The first of ten frames fails (POV-Ray stops at it); the other nine are rendered by a second run.
// Ten frames also take POV-Ray's two-digit frame numbers in the output names.
TEST(RaytraceRender, AFrameThatFailsIsReportedAndTheOthersGoOn) {
  REQUIRE_POVRAY();
  const FreshDir scratch("failing");
  const fs::path& dir = scratch.path;
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
  const FreshDir scratch("broken");
  const fs::path& dir = scratch.path;
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

}  // namespace test_render
