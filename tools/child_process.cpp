#include "tools/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <thread>
#include <stdexcept>

namespace tagbench {

ChildStatus run_child(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                      const std::filesystem::path& log, int nice_increment) {
  if (argv.empty()) throw std::invalid_argument("run_child: no program");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string dir = cwd.string(), logfile = log.string();
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": fork failed");
  if (pid == 0) {  // only async-signal-safe calls from here on
    // The signal comes when the forking thread ends, and that thread waits for this child.
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(126);
    const int fd = ::open(logfile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_RDONLY);
    if (fd < 0 || null < 0 || ::chdir(dir.c_str()) != 0) ::_exit(126);
    ::dup2(null, 0);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    if (fd > 2) ::close(fd);
    if (null > 2) ::close(null);
    if (nice_increment != 0 && ::nice(nice_increment) == -1) {
      // a failed nice is harmless
    }
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("waiting for " + argv[0] + " failed");
  }
  ChildStatus s;
  if (WIFSIGNALED(st)) s.signal = WTERMSIG(st);
  else if (WIFEXITED(st)) s.exit_code = WEXITSTATUS(st);
  return s;
}

ChildStatus run_child_io(const std::vector<std::string>& argv, const std::filesystem::path& cwd, const ChildIo& io) {
  if (argv.empty()) throw std::invalid_argument("run_child_io: no program");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string dir = cwd.string(), in = io.stdin_file.string(), out = io.stdout_file.string(),
                    err = io.stderr_file.string();
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": fork failed");
  if (pid == 0) {  // only async-signal-safe calls from here on
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(126);
    ::setpgid(0, 0);
    const int i = ::open(in.c_str(), O_RDONLY);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (i < 0 || o < 0 || e < 0 || ::chdir(dir.c_str()) != 0) ::_exit(126);
    ::dup2(i, 0);
    ::dup2(o, 1);
    ::dup2(e, 2);
    for (const int fd : {i, o, e})
      if (fd > 2) ::close(fd);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here, so the group exists before any kill below
  ChildStatus s;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(io.timeout_seconds);
  int st = 0;
  while (true) {
    const pid_t r = ::waitpid(pid, &st, io.timeout_seconds > 0 ? WNOHANG : 0);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) throw std::runtime_error("waiting for " + argv[0] + " failed");
    if (io.timeout_seconds > 0 && std::chrono::steady_clock::now() >= deadline) {
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      s.timed_out = true;
      while (::waitpid(pid, &st, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    if (r == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFSIGNALED(st)) s.signal = WTERMSIG(st);
  else if (WIFEXITED(st)) s.exit_code = WEXITSTATUS(st);
  return s;
}

}  // namespace tagbench
