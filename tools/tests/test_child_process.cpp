// Running a child program: its exit code or signal, its output in the log, its folder, and the
// codes for what could not be run.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scratch_dir.hpp"
#include "tools/child_process.hpp"

namespace test_child_process {

namespace fs = std::filesystem;
using tagbench::ChildStatus;
using tagbench::run_child;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class ChildProcess : public ::testing::Test {
 protected:
  tagbench::testing::ScratchDir dir_{"child_process"};
};

}  // namespace

TEST_F(ChildProcess, ExitCodeAndOutputInTheLog) {
  const fs::path log = dir_.path() / "out.log";
  const ChildStatus s = run_child({"sh", "-c", "echo out; echo err >&2; exit 3"}, dir_.path(), log);
  EXPECT_EQ(s.exit_code, 3);
  EXPECT_EQ(s.signal, 0);
  EXPECT_EQ(s.code(), 3);
  EXPECT_EQ(slurp(log), "out\nerr\n");
}

TEST_F(ChildProcess, RunsInTheGivenFolderWithNoInput) {
  fs::create_directories(dir_.path() / "sub");
  const fs::path log = dir_.path() / "pwd.log";
  const ChildStatus s = run_child({"sh", "-c", "pwd; cat; echo done"}, dir_.path() / "sub", log);
  EXPECT_EQ(s.code(), 0);
  EXPECT_EQ(slurp(log), fs::canonical(dir_.path() / "sub").string() + "\ndone\n");
}

TEST_F(ChildProcess, ARelativeLogIsTakenFromOurFolderNotTheChilds) {
  fs::create_directories(dir_.path() / "work");
  const fs::path here = fs::current_path();
  fs::current_path(dir_.path());
  const ChildStatus s = run_child({"sh", "-c", "echo hi"}, "work", "rel.log");
  fs::current_path(here);
  EXPECT_EQ(s.code(), 0);
  EXPECT_EQ(slurp(dir_.path() / "rel.log"), "hi\n");
  EXPECT_FALSE(fs::exists(dir_.path() / "work" / "rel.log"));
}

TEST_F(ChildProcess, ASignalIsReportedAsSuch) {
  const ChildStatus s = run_child({"sh", "-c", "kill -TERM $$"}, dir_.path(), dir_.path() / "sig.log");
  EXPECT_EQ(s.signal, 15);
  EXPECT_EQ(s.code(), 128 + 15);
}

TEST_F(ChildProcess, WhatCannotRunGets127AndAMissingFolder126) {
  EXPECT_EQ(run_child({"/nonexistent/program"}, dir_.path(), dir_.path() / "a.log").code(), 127);
  EXPECT_EQ(run_child({"no-such-program-tagbench"}, dir_.path(), dir_.path() / "b.log").code(), 127);
  EXPECT_EQ(run_child({"sh", "-c", "true"}, dir_.path() / "missing", dir_.path() / "c.log").code(), 126);
  EXPECT_THROW(run_child({}, dir_.path(), dir_.path() / "d.log"), std::invalid_argument);
}

TEST_F(ChildProcess, NiceLowersThePriority) {
  // `nice` without arguments prints the niceness it runs at.
  ASSERT_EQ(run_child({"nice"}, dir_.path(), dir_.path() / "base.log").code(), 0);
  ASSERT_EQ(run_child({"nice"}, dir_.path(), dir_.path() / "nice.log", 5).code(), 0);
  const int base = std::stoi(slurp(dir_.path() / "base.log"));
  EXPECT_EQ(std::stoi(slurp(dir_.path() / "nice.log")), std::min(base + 5, 19));
}

TEST_F(ChildProcess, IoFromAndIntoFilesAndATimeLimitThatEndsTheGroup) {
  const fs::path in = dir_.path() / "in", out = dir_.path() / "out", err = dir_.path() / "err";
  std::ofstream(in) << "a\nb\n";
  tagbench::ChildIo io{in, out, err, 0};
  ChildStatus s = tagbench::run_child_io({"sh", "-c", "tac; echo e >&2"}, dir_.path(), io);
  EXPECT_EQ(s.code(), 0);
  EXPECT_FALSE(s.timed_out);
  EXPECT_EQ(slurp(out), "b\na\n");
  EXPECT_EQ(slurp(err), "e\n");
  // A hang (here in a grandchild) is killed at the limit, with everything it started.
  io.timeout_seconds = 0.3;
  const auto t0 = std::chrono::steady_clock::now();
  s = tagbench::run_child_io({"sh", "-c", "sleep 30 & wait"}, dir_.path(), io);
  EXPECT_TRUE(s.timed_out);
  EXPECT_EQ(s.signal, SIGKILL);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10);
}

// A signal this process ignores (SIGHUP under nohup) stays ignored while a child runs: the child is
// not killed for it, and the disposition is the same afterwards.
TEST_F(ChildProcess, AnIgnoredSignalDoesNotKillTheChild) {
  const fs::path in = dir_.path() / "in2", out = dir_.path() / "out2", err = dir_.path() / "err2";
  std::ofstream(in) << "";
  const auto previous = std::signal(SIGHUP, SIG_IGN);
  const ChildStatus s = tagbench::run_child_io({"sh", "-c", "kill -HUP $PPID; sleep 0.2; echo done"}, dir_.path(),
                                               tagbench::ChildIo{in, out, err, 20});
  const auto during = std::signal(SIGHUP, previous);
  EXPECT_EQ(s.code(), 0) << "killed by signal " << s.signal;
  EXPECT_EQ(slurp(out), "done\n");
  EXPECT_EQ(during, SIG_IGN);
}

}  // namespace test_child_process
