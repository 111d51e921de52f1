// External detectors inside `tagbench raytrace` (issue 12, section 3): our own `tagbench detect
// --format jsonl` run as an external detector gives exactly the built-in rows of the same detector,
// the example adapter examples/external/aruco_detector.py exactly the built-in aruco rows, and a
// failing external detector stops the run with one line and no output.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "../../raytrace/tests/test_frames.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_external {

namespace fs = std::filesystem;

namespace {

using tagbench::testing::CommandResult;
using tagbench::testing::run_tagbench;
using tagbench::testing::shell_quote;
using tagbench::testing::slurp;

std::string sweep() {
  return "raytrace angle --angles 0,40,70 --trials 2 --processes 1 --cache " + tagbench::bench::test::shared_cache().string();
}

// The rows of `detector`, without its name and timing (`ms`) columns, and without the loss stage
// (`loss_stage`, `loss_bits`: ours explains a missed frame, an external detector cannot).
std::vector<std::string> rows_of(const std::string& csv, const std::string& detector) {
  std::vector<std::string> out;
  std::istringstream in(csv);
  std::size_t name_col = 0, ms_col = 0, loss_col = 0;
  bool header = true;
  for (std::string l; std::getline(in, l);) {
    std::vector<std::string> cells;
    std::istringstream cs(l);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    if (!l.empty() && l.back() == ',') cells.push_back("");
    if (header) {
      name_col = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "detector") - cells.begin());
      ms_col = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "ms") - cells.begin());
      loss_col = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "loss_stage") - cells.begin());
      header = false;
      continue;
    }
    if (name_col >= cells.size() || cells[name_col] != detector) continue;
    std::string row;
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i != name_col && i != ms_col && i != loss_col && i != loss_col + 1) row += cells[i] + ",";
    out.push_back(row);
  }
  return out;
}

TEST(CliExternal, OurDetectorAsAnExternalOneGivesTheBuiltInRows) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  tagbench::testing::ScratchDir dir("tagbench_cli_external");
  const std::string ours = std::string(TAGBENCH_BIN) + " detect - --format jsonl --family 36h11 --camera 400,400,199.5,199.5 --tag-size 0.166 --input-gamma 1";
  const std::string list = "tagbench,tagbench-half,external:mine-full=" + ours + ",external:mine-half=" + ours + " --half-res";
  const CommandResult r = run_tagbench(sweep() + " --detectors " + shell_quote(list) + " --out " + (dir / "o").string(), dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir / "o" / "fig9_angle.csv");
  EXPECT_EQ(rows_of(csv, "mine-full").size(), 6u);
  EXPECT_EQ(rows_of(csv, "mine-full"), rows_of(csv, "tagbench"));
  EXPECT_EQ(rows_of(csv, "mine-half"), rows_of(csv, "tagbench-half"));
  EXPECT_NE(slurp(dir / "o" / "fig9_angle.json").find("\"external\": [{\"name\": \"mine-full\""), std::string::npos);
}

TEST(CliExternal, OurDetectorAsAnExternalOneGivesTheBuiltInRowsOnTheSixdofSweep) {
  // The 6-DoF sweep's camera has a lens: the external detector is told it as ours is (--distortion).
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  tagbench::testing::ScratchDir dir("tagbench_cli_external");
  const std::string ours = std::string(TAGBENCH_BIN) +
                           " detect - --format jsonl --family 36h11 --camera 400,400,199.5,199.5 --tag-size 0.166"
                           " --distortion -0.2,0.05,0.001,-0.0005,0 --input-gamma 1";
  const std::string list = "tagbench,tagbench-half,external:mine-full=" + ours + ",external:mine-half=" + ours + " --half-res";
  const CommandResult r = run_tagbench("raytrace sixdof --frames 5 --distance-range 0.5,3 --processes 1 --cache " +
                                           tagbench::bench::test::shared_cache().string() + " --detectors " +
                                           shell_quote(list) + " --out " + (dir / "o").string(),
                                       dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir / "o" / "sixdof.csv");
  EXPECT_EQ(rows_of(csv, "mine-full").size(), 5u);
  EXPECT_EQ(rows_of(csv, "mine-full"), rows_of(csv, "tagbench"));
  EXPECT_EQ(rows_of(csv, "mine-half"), rows_of(csv, "tagbench-half"));
  EXPECT_NE(csv.find(",tagbench,1,"), std::string::npos) << "some frame detected: the comparison means something";
}

TEST(CliExternal, TheExampleArucoAdapterGivesTheBuiltInArucoRows) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  if (std::system("/usr/bin/python3 -c 'import cv2' 2>/dev/null") != 0)
    GTEST_SKIP() << "python3-opencv not installed (scripts/install-deps.sh installs it)";
  tagbench::testing::ScratchDir dir("tagbench_cli_external");
  const std::string adapter = std::string(TAGBENCH_SOURCE_DIR) + "/examples/external/aruco_detector.py";
  const std::string list =
      "aruco,external:aruco-py=/usr/bin/python3 " + adapter + " --camera 400,400,199.5,199.5 --tag-size 0.166";
  const CommandResult r = run_tagbench(sweep() + " --detectors " + shell_quote(list) + " --out " + (dir / "o").string(), dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir / "o" / "fig9_angle.csv");
  EXPECT_EQ(rows_of(csv, "aruco-py").size(), 6u);
  // The same OpenCV library on the same pixels: equal to the last digit.
  EXPECT_EQ(rows_of(csv, "aruco-py"), rows_of(csv, "aruco"));
}

TEST(CliExternal, TheExampleArucoAdapterGivenTheLensGivesTheBuiltInArucoRowsOnTheSixdofSweep) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  if (std::system("/usr/bin/python3 -c 'import cv2' 2>/dev/null") != 0)
    GTEST_SKIP() << "python3-opencv not installed (scripts/install-deps.sh installs it)";
  tagbench::testing::ScratchDir dir("tagbench_cli_external");
  const std::string adapter = std::string(TAGBENCH_SOURCE_DIR) + "/examples/external/aruco_detector.py";
  const std::string list = "aruco,external:aruco-py=/usr/bin/python3 " + adapter +
                           " --camera 400,400,199.5,199.5 --tag-size 0.166 --distortion -0.2,0.05,0.001,-0.0005,0";
  const CommandResult r = run_tagbench("raytrace sixdof --frames 5 --distance-range 0.5,2 --processes 1 --cache " +
                                           tagbench::bench::test::shared_cache().string() + " --detectors " +
                                           shell_quote(list) + " --out " + (dir / "o").string(),
                                       dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir / "o" / "sixdof.csv");
  EXPECT_EQ(rows_of(csv, "aruco-py").size(), 5u);
  EXPECT_EQ(rows_of(csv, "aruco-py"), rows_of(csv, "aruco"));
  EXPECT_NE(csv.find(",aruco,1,"), std::string::npos) << "some frame detected: the comparison means something";
}

TEST(CliExternal, AFailingExternalDetectorIsOneLineAndWritesNothing) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  tagbench::testing::ScratchDir dir("tagbench_cli_external");
  CommandResult r = run_tagbench(sweep() + " --detectors " + shell_quote("tagbench,external:bad=sh -c 'read a; exit 4'") +
                                     " --out " + (dir / "o").string(),
                                 dir.path());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("external detector bad: exited with status 4 at image '"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
  r = run_tagbench(sweep() + " --external-timeout 0.5 --detectors " + shell_quote("external:slow=sleep 60") + " --out " +
                       (dir / "o").string(),
                   dir.path());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("external detector slow: no end within 0.5 s (--external-timeout)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
  r = run_tagbench(sweep() + " --detectors " + shell_quote("external:x=a 'b") + " --out " + (dir / "o").string(), dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unclosed single quote"), std::string::npos) << r.err;
}


// Ctrl-C while an external detector runs: the detector's process group (which the terminal's signal
// does not reach, being a group of its own) is killed with us, its own children too, and the work
// folder our killed run left is removed by the next run that starts an external detector.
TEST(CliExternal, SigintKillsTheDetectorsChildrenAndTheNextRunRemovesTheWorkFolder) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  tagbench::testing::ScratchDir dir("tagbench_cli_external_sigint");
  const fs::path tmp = dir / "tmp", gc = dir / "grandchild.pid";
  fs::create_directories(tmp);
  const std::string detector = "external:slow=sh -c 'sleep 300 & echo $! > " + gc.string() + "; wait'";
  std::string cmd = "exec " + std::string(TAGBENCH_BIN) + " " + sweep() + " --detectors " + shell_quote(detector) +
                    " --out " + shell_quote((dir / "o").string()) + " >/dev/null 2>/dev/null </dev/null";
  // TMPDIR for the runs below (and put back however this test ends).
  struct TmpdirGuard {
    bool had = std::getenv("TMPDIR") != nullptr;
    std::string saved = had ? std::getenv("TMPDIR") : "";
    ~TmpdirGuard() {
      if (had) ::setenv("TMPDIR", saved.c_str(), 1);
      else ::unsetenv("TMPDIR");
    }
  } tmpdir_guard;
  ::setenv("TMPDIR", tmp.c_str(), 1);
  const pid_t pid = ::fork();
  if (pid == 0) {
    // SIGINT as a terminal's foreground job gets it, whatever the test runner was started with.
    ::signal(SIGINT, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  int st = 0;
  bool ended = false;  // tagbench ended before the detector started (it should not)
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  while (!(fs::exists(gc) && !slurp(gc).empty()) && std::chrono::steady_clock::now() < deadline) {
    if (::waitpid(pid, &st, WNOHANG) == pid) {
      ended = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!ended) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ::kill(pid, SIGINT);
    ASSERT_EQ(::waitpid(pid, &st, 0), pid);
  }
  ASSERT_FALSE(ended) << "tagbench ended before the external detector ran: status " << st;
  EXPECT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == SIGINT) << st;
  const int gc_pid = std::atoi(slurp(gc).c_str());
  ASSERT_GT(gc_pid, 0);
  // Gone, or a zombie waiting for a reaper (the sleep was killed).
  const auto alive = [&] {
    const std::string stat = slurp("/proc/" + std::to_string(gc_pid) + "/stat");
    const auto close = stat.rfind(')');
    return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] != 'Z';
  };
  for (int i = 0; i < 100 && alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(alive()) << "the external detector's child outlived the run";
  const auto work_folders = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(tmp)) n += e.path().filename().string().rfind("tagbench-external-", 0) == 0;
    return n;
  };
  EXPECT_EQ(work_folders(), 1) << "the killed run's work folder";
  EXPECT_FALSE(fs::exists(dir / "o"));
  const CommandResult r = run_tagbench(sweep() + " --detectors " + shell_quote("external:bad=sh -c 'read a; exit 4'") +
                                           " --out " + (dir / "o").string(),
                                       dir.path());
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(work_folders(), 0);
}

}  // namespace

}  // namespace test_cli_external
