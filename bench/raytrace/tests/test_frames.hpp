#pragma once
// Ray-traced frames shared by the raytrace tests: a few plain-scene poses, rendered once into a cache
// that every test process shares (frames are keyed by content, and concurrent renders of the same
// frame are safe), so each test renders at most a handful of frames. Also the listing of a folder the
// render tests write to, and the corner error they measure found corners by.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "raytrace/render.hpp"

namespace tagbench::bench::test {

// 36h11 ids 0, 137 and 586; tilted about several axes, turned in the plane, off the image centre.
inline std::vector<FramePose> plain_frames() {
  std::vector<FramePose> f(3);
  f[0].id = 0;
  f[0].pose = view_pose({.distance = 0.8, .phi_deg = 45, .tilt_axis_deg = 20, .roll_deg = 0, .pixel = {230.0, 180.0}});
  f[1].id = 137;
  f[1].pose = view_pose({.distance = 1.0, .phi_deg = 25, .tilt_axis_deg = 100, .roll_deg = 130, .pixel = {170.0, 215.0}});
  f[2].id = 586;
  f[2].pose = view_pose({.distance = 0.6, .phi_deg = 60, .tilt_axis_deg = -35, .roll_deg = -70, .pixel = {205.0, 195.0}});
  return f;
}

inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto d = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::create_directories(d);
  return d;
}

// The names of the files in `dir`.
inline std::set<std::string> files_in(const std::filesystem::path& dir) {
  std::set<std::string> s;
  for (const auto& e : std::filesystem::directory_iterator(dir)) s.insert(e.path().filename().string());
  return s;
}

// The largest distance between corresponding corners of `a` and `b`, in pixels.
inline double max_corner_error(const Corners& a, const Corners& b) {
  double m = 0;
  for (std::size_t k = 0; k < 4; ++k) m = std::max(m, (a[k] - b[k]).norm());
  return m;
}

// The cache the test processes share.
inline std::filesystem::path shared_cache() { return scratch_dir("tagbench_raytrace_test_cache"); }

// One povray process at a time, niced: the tests must not crowd the machine.
inline RenderOptions gentle_options(const std::filesystem::path& cache) {
  RenderOptions o;
  o.cache_dir = cache;
  o.processes = 1;
  o.nice = 5;
  return o;
}

inline bool have_povray() { return find_povray().has_value(); }

// Skips the calling test where POV-Ray is not installed.
#define REQUIRE_POVRAY() \
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray is not installed"

}  // namespace tagbench::bench::test
