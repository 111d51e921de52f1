#pragma once
// Shared by the interruption tests: start `tagbench ARGS` as a child of the test (so it can be
// killed with kill -9 by its pid), wait for a sign that it is in the middle of its work, kill it, and
// look at what it left. The sign is something the run makes (a file appears, CPU time is spent), never
// a fixed sleep, so the kill lands mid-run on a loaded machine too; kill_when reports whether it did.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run_tagbench.hpp"

namespace tagbench::testing {

// Starts `TAGBENCH_BIN ARGS` (words split by /bin/sh; `env` like "PATH=/x:$PATH" goes before it) with
// stdout and stderr into files in `dir`, stdin from /dev/null. `file_size_limit` > 0: RLIMIT_FSIZE
// in bytes, with SIGXFSZ ignored so that writes past it fail with EFBIG (a full disk).
inline pid_t start_tagbench(const std::string& args, const std::filesystem::path& dir, const std::string& env = "",
                            long long file_size_limit = 0) {
  const std::string cmd = "exec " + (env.empty() ? std::string() : "env " + env + " ") + TAGBENCH_BIN + " " + args +
                          " >" + shell_quote((dir / "stdout").string()) + " 2>" +
                          shell_quote((dir / "stderr").string()) + " </dev/null";
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (file_size_limit > 0) {
      const rlimit r{static_cast<rlim_t>(file_size_limit), static_cast<rlim_t>(file_size_limit)};
      ::signal(SIGXFSZ, SIG_IGN);  // kept across exec
      if (::setrlimit(RLIMIT_FSIZE, &r) != 0) ::_exit(126);
    }
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// Waits for a started run to end; its exit status as CommandResult::code (128 + signal when killed).
inline CommandResult wait_tagbench(pid_t pid, const std::filesystem::path& dir) {
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return {WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st), slurp(dir / "stdout"), slurp(dir / "stderr")};
}

// `tagbench ARGS` to the end, as run_tagbench, but with the options of start_tagbench.
inline CommandResult run_tagbench_with(const std::string& args, const std::filesystem::path& dir,
                                       const std::string& env, long long file_size_limit = 0) {
  return wait_tagbench(start_tagbench(args, dir, env, file_size_limit), dir);
}

struct KillOutcome {
  bool killed_mid_run = false;  // `ready` held while the run was still going, and kill -9 ended it
  std::string why;              // otherwise: what happened instead
};

// Polls `ready` about every millisecond; once it holds, kill -9 the run and reap it. Gives up (and
// kills it anyway) after `timeout`.
inline KillOutcome kill_when(pid_t pid, const std::function<bool()>& ready,
                             std::chrono::seconds timeout = std::chrono::seconds(120)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int st = 0;
  while (true) {
    if (ready()) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
      }
      if (WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL) return {true, ""};
      return {false, "the run ended (status " + std::to_string(st) + ") just before the kill"};
    }
    const pid_t w = ::waitpid(pid, &st, WNOHANG);
    if (w == pid)
      return {false, "the run ended before it could be killed (exit " +
                         std::to_string(WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st)) + ")"};
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &st, 0);
      return {false, "timed out waiting for the run to get going"};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// CPU seconds (user + system, all threads) process `pid` has used so far; 0 when it cannot be read.
inline double cpu_seconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const auto close = stat.rfind(')');  // the command name may hold spaces and parentheses
  if (close == std::string::npos) return 0;
  std::istringstream f(stat.substr(close + 2));
  std::string field;
  unsigned long long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && f >> field; ++i) {  // fields 14 and 15 are utime and stime, in ticks
    if (i == 14) utime = std::stoull(field);
    if (i == 15) stime = std::stoull(field);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// Pids of the processes whose working directory is `dir` (what a killed run may have left running).
inline std::vector<pid_t> processes_working_in(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path want = fs::weakly_canonical(dir, ec);
  std::vector<pid_t> out;
  for (fs::directory_iterator it("/proc", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code rec;
    const fs::path cwd = fs::read_symlink(it->path() / "cwd", rec);
    if (!rec && cwd == want) out.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return out;
}

// Every regular file under `dir` (relative path, generic form) with its bytes: two trees compare
// equal when they hold the same files, byte for byte, and nothing else.
inline std::map<std::string, std::string> file_tree(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).generic_string()] = slurp(e.path());
  return out;
}

// The names of two trees that differ (missing on one side or other bytes), for a readable failure.
inline std::string tree_difference(const std::map<std::string, std::string>& a,
                                   const std::map<std::string, std::string>& b) {
  std::string d;
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    if (it == b.end()) d += "  only in the first: " + k + "\n";
    else if (it->second != v) d += "  differs: " + k + "\n";
  }
  for (const auto& [k, v] : b)
    if (!a.count(k)) d += "  only in the second: " + k + "\n";
  return d;
}

}  // namespace tagbench::testing
