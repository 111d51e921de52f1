// `tagbench raytrace` interrupted and in parallel (issue 6, items 4 and 5): a sweep killed with kill -9
// while POV-Ray renders, run again with the same frame cache, writes the rows, summary and settings
// of an uninterrupted run (all but the timing columns and the render report), leaves no POV-Ray
// running and nothing of the killed run in the cache; and one povray process or three render the
// same frames, so the results are the same.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "csv_timing.hpp"
#include "raytrace/render.hpp"
#include "test_frames.hpp"
#include "tools/atomic_file.hpp"

#include "kill_run.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_raytrace_interruption {

namespace fs = std::filesystem;
using namespace tagbench::testing;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d =
      program_scratch("tagbench_raytrace_interruption") / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Six frames (two trials at three angles), three detectors: a few seconds of POV-Ray.
const std::string kSweep = "raytrace angle --trials 2 --angles 0,30,60 --seed 5 "
                           "--detectors tagbench-paper,libapriltag-d1,aruco";

std::string sweep(const fs::path& cache, const fs::path& out, int processes) {
  return kSweep + " --processes " + std::to_string(processes) + " --cache " + cache.string() + " --out " +
         out.string();
}

// A CSV without its last column (the timing: ms in the rows, ms_median in the summary).
std::string without_timing(const std::string& csv) { return tagbench::testing::csv_without_timing(csv); }

// The JSON sidecar without the render report's counts and times, which say how the frames were
// obtained (rendered, from the cache, in how many povray runs), not what they are.
std::string without_render_report(const std::string& json) {
  std::istringstream in(json);
  std::string out;
  for (std::string l; std::getline(in, l);)
    if (l.find("\"rendered\":") == std::string::npos && l.find("\"render_seconds\":") == std::string::npos)
      out += l + "\n";
  return out;
}

void expect_same_results(const fs::path& a, const fs::path& b) {
  const std::string rows = slurp(a / "fig9_angle.csv");
  ASSERT_EQ(std::count(rows.begin(), rows.end(), '\n'), 1 + 6 * 3) << rows;
  EXPECT_EQ(without_timing(slurp(b / "fig9_angle.csv")), without_timing(rows));
  EXPECT_EQ(without_timing(slurp(b / "fig9_angle_summary.csv")), without_timing(slurp(a / "fig9_angle_summary.csv")));
  EXPECT_EQ(without_render_report(slurp(b / "fig9_angle.json")), without_render_report(slurp(a / "fig9_angle.json")));
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  return v;
}

// Two cached frames have the same pixels (their PNG bytes differ: POV-Ray writes the render date).
bool same_pixels(const fs::path& a, const fs::path& b) {
  const cv::Mat x = cv::imread(a.string(), cv::IMREAD_UNCHANGED), y = cv::imread(b.string(), cv::IMREAD_UNCHANGED);
  return !x.empty() && x.size() == y.size() && x.type() == y.type() && cv::norm(x, y, cv::NORM_INF) == 0;
}

}  // namespace

TEST(RaytraceInterruption, KilledWhileRenderingThenRerunWithTheSameCacheGivesTheUninterruptedResults) {
  REQUIRE_POVRAY();
  const fs::path ref_cache = scratch("ref-cache"), ref_out = scratch("ref-out");
  const CommandResult ref = run_tagbench(sweep(ref_cache, ref_out, 1), scratch("ref-log"));
  ASSERT_EQ(ref.code, 0) << ref.err;

  // One povray process renders the six frames under temporary names, moved into the cache only when
  // its run ends: killed once the first of them is out, five are still to come.
  const fs::path cache = scratch("cache"), out = scratch("out"), log = scratch("kill-log");
  const pid_t pid = start_tagbench(sweep(cache, out, 1), log);
  const auto rendering = [&] {
    for (const auto& n : names_in(cache))
      if (n.rfind("tmp-", 0) == 0 && n.size() > 4 && n.ends_with(".png")) return true;
    return false;
  };
  const KillOutcome k = kill_when(pid, rendering);
  ASSERT_TRUE(k.killed_mid_run) << k.why << "\n" << slurp(log / "stderr");
  EXPECT_TRUE(fs::is_empty(out)) << "no results from a killed run";
  // POV-Ray went with it (an orphan would render its remaining frames for another second or more).
  std::vector<pid_t> left;
  for (int i = 0; i < 500 && !(left = processes_working_in(cache)).empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_TRUE(left.empty()) << left.size() << " process(es) still working in the cache, e.g. pid " << left[0];
  // As a kill while the results were written would leave them.
  const fs::path stale = tagbench::atomic_temporary(out / "fig9_angle.csv", pid);
  std::ofstream(stale) << "half a file";

  const CommandResult again = run_tagbench(sweep(cache, out, 1), scratch("rerun-log"));
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("6 frames (6 distinct: "), std::string::npos) << again.err;
  expect_same_results(ref_out, out);
  EXPECT_FALSE(fs::exists(stale));
  // Nothing of the killed run is left in the cache: its scene, log and unfinished frames are gone.
  for (const auto& n : names_in(cache))
    EXPECT_TRUE(n.rfind("frame-", 0) == 0 || n.rfind("tag-", 0) == 0) << "left in the cache: " << n;
  // And the cached frames are those of the uninterrupted run, pixel for pixel.
  for (const auto& n : names_in(ref_cache)) EXPECT_TRUE(same_pixels(cache / n, ref_cache / n)) << n;
}

TEST(RaytraceDeterminism, OnePovrayProcessOrThreeGiveTheSameResults) {
  REQUIRE_POVRAY();
  const fs::path c1 = scratch("p1-cache"), o1 = scratch("p1-out"), c3 = scratch("p3-cache"), o3 = scratch("p3-out");
  const CommandResult one = run_tagbench(sweep(c1, o1, 1), scratch("p1-log"));
  ASSERT_EQ(one.code, 0) << one.err;
  const CommandResult three = run_tagbench(sweep(c3, o3, 3), scratch("p3-log"));
  ASSERT_EQ(three.code, 0) << three.err;
  EXPECT_NE(three.err.find("6 rendered"), std::string::npos) << "rendered afresh, not from the cache: " << three.err;
  expect_same_results(o1, o3);
  const auto frames = names_in(c1);
  EXPECT_EQ(frames.size(), names_in(c3).size());
  for (const auto& n : frames) EXPECT_TRUE(same_pixels(c3 / n, c1 / n)) << n;
}

}  // namespace test_raytrace_interruption
