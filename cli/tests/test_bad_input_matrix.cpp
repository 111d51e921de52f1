// The bad-input matrix (issue 6, item 3): one table of hostile inputs to the `tagbench` commands
// (in test_bad_input_cases.cpp), each case run here as a test of its own.
// Every case runs the real program in a fresh scratch folder (its working directory) and asserts:
//   - the expected exit code, a normal exit (no signal, no core dump, code < 128);
//   - on an error, exactly one line on stderr that names the input and the problem;
//     on success (valid but odd inputs), nothing on stderr and the expected text on stdout;
//   - the scratch folder lists the same files with the same sizes after the run as before it:
//     no output, no partial output and no temporary beside it is left behind.
// A full disk is simulated with RLIMIT_FSIZE and SIGXFSZ ignored in the child, so its writes fail
// with EFBIG like on a full file system; stdout and stderr are pipes, which the limit does not touch.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "bad_input_util.hpp"

extern char** environ;

namespace test_bad_input {

// ---- the child process --------------------------------------------------------------------------

// Runs `tagbench args` in `cwd` with stdin from /dev/null and stdout/stderr read through pipes.
ChildRun run_child(const fs::path& cwd, const std::vector<std::string>& args, const Limits& lim) {
  // Everything the child needs is built before fork: after it only async-signal-safe calls.
  std::vector<std::string> words = {TAGBENCH_BIN};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_words;
  for (char** e = environ; *e; ++e)
    if (!lim.path || std::strncmp(*e, "PATH=", 5) != 0) env_words.emplace_back(*e);
  if (lim.path) env_words.push_back("PATH=" + (cwd / lim.path).string());
  std::vector<char*> envp;
  for (auto& w : env_words) envp.push_back(w.data());
  envp.push_back(nullptr);
  const std::string dir = cwd.string();

  int out[2], err[2];
  if (::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    const int null = ::open("/dev/null", O_RDONLY);
    if (::chdir(dir.c_str()) != 0 || null < 0 || ::dup2(null, 0) < 0 || ::dup2(out[1], 1) < 0 ||
        ::dup2(err[1], 2) < 0)
      ::_exit(126);
    if (lim.fsize > 0) {
      const rlimit r{static_cast<rlim_t>(lim.fsize), static_cast<rlim_t>(lim.fsize)};
      ::signal(SIGXFSZ, SIG_IGN);  // kept across exec: writes past the limit fail with EFBIG
      if (::setrlimit(RLIMIT_FSIZE, &r) != 0) ::_exit(126);
    }
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  ::close(out[1]);
  ::close(err[1]);
  ChildRun r;
  std::array<pollfd, 2> fds{{{out[0], POLLIN, 0}, {err[0], POLLIN, 0}}};
  std::string* sinks[2] = {&r.out, &r.err};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  int open_fds = 2;
  while (open_fds > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {  // a hang is a failure, not a stuck test run
      r.timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    if (::poll(fds.data(), fds.size(), static_cast<int>(std::min<long long>(left.count(), 1000))) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char buf[65536];
      const ssize_t n = ::read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        sinks[i]->append(buf, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_fds;
      }
    }
  }
  for (const auto& f : fds)
    if (f.fd >= 0) ::close(f.fd);
  while (::waitpid(pid, &r.status, 0) < 0 && errno == EINTR) {
  }
  return r;
}

namespace {

// ---- the scratch folder -------------------------------------------------------------------------

struct Scratch {
  fs::path dir;
  Scratch() {
    std::string templ = (fs::path(::testing::TempDir()) / "tagbench_bad_input_XXXXXX").string();
    if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    dir = templ;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// Every entry under `dir`, sorted: relative path, type and (for files) size.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> out;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    const auto st = it->symlink_status();
    std::string e = fs::relative(it->path(), dir).string();
    if (fs::is_directory(st)) e += "/";
    else if (fs::is_regular_file(st)) e.append(" ").append(std::to_string(fs::file_size(it->path())));
    out.push_back(e);
  }
  std::sort(out.begin(), out.end());
  return out;
}

class BadInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadInput, RefusedCleanly) {
  const Case& c = GetParam();
  const Scratch scratch;
  if (c.setup) c.setup(scratch.dir);
  const std::vector<std::string> before = listing(scratch.dir);
  std::string cmd = "tagbench";
  for (const auto& a : c.args) cmd += " " + a;
  SCOPED_TRACE(cmd);

  const ChildRun r = run_child(scratch.dir, c.args, c.limits);
  ASSERT_FALSE(r.timed_out) << "no exit within 5 minutes";
  ASSERT_TRUE(WIFEXITED(r.status)) << "killed by signal " << WTERMSIG(r.status)
                                   << (WCOREDUMP(r.status) ? " (core dumped)" : "") << "\nstderr: " << r.err;
  const int code = WEXITSTATUS(r.status);
  EXPECT_EQ(code, c.code) << "stderr: " << r.err;
  EXPECT_LT(code, 128);
  if (c.code != 0) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    EXPECT_TRUE(r.err.ends_with("\n")) << r.err;
    EXPECT_TRUE(r.err.starts_with("tagbench")) << r.err;
    for (const auto& e : c.expect) EXPECT_NE(r.err.find(e), std::string::npos) << "'" << e << "' not in: " << r.err;
  } else {
    EXPECT_EQ(r.err, "");
    for (const auto& e : c.expect) EXPECT_NE(r.out.find(e), std::string::npos) << "'" << e << "' not in: " << r.out;
  }
  // No output, no partial output, no temporary and no core file.
  EXPECT_EQ(listing(scratch.dir), before);
}

INSTANTIATE_TEST_SUITE_P(Matrix, BadInput, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

}  // namespace

}  // namespace test_bad_input
