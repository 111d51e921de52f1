#include "tools/child_process.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <mutex>
#include <chrono>
#include <thread>
#include <stdexcept>

namespace tagbench {

namespace {

// The process groups of run_child_io's children still running. They are not in our process group,
// so a Ctrl-C at the terminal does not reach them; while any runs, SIGINT, SIGTERM and SIGHUP kill
// every such group before the signal takes its earlier course (by default, ending this process).
// Without it the child's own children outlive us (PR_SET_PDEATHSIG reaches only the direct child).
constexpr int kGroupSlots = 64;
std::atomic<pid_t> g_groups[kGroupSlots];
constexpr int kForwarded[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[3];
bool g_installed[3];     // a signal that was ignored (nohup, a background job) is left ignored
std::mutex g_groups_mu;  // guards g_running and the installing and restoring of the handlers
int g_running = 0;

extern "C" void kill_child_groups(int sig) {
  const int saved_errno = errno;
  for (auto& g : g_groups)
    if (const pid_t p = g.load(); p > 0) ::kill(-p, SIGKILL);
  for (int i = 0; i < 3; ++i)
    if (kForwarded[i] == sig) ::sigaction(sig, &g_previous[i], nullptr);
  ::raise(sig);  // the earlier course: by default the end of this process
  errno = saved_errno;
}

// SIGINT, SIGTERM and SIGHUP blocked while a child is forked and registered, so that none arrives
// between the fork and the registration (the child's group would outlive us).
class ForwardedBlocked {
 public:
  ForwardedBlocked() {
    sigset_t s;
    sigemptyset(&s);
    for (const int sig : kForwarded) sigaddset(&s, sig);
    ::pthread_sigmask(SIG_BLOCK, &s, &old_);
  }
  ~ForwardedBlocked() { restore(); }
  void restore() {
    if (!restored_) ::pthread_sigmask(SIG_SETMASK, &old_, nullptr);
    restored_ = true;
  }
  const sigset_t& old() const { return old_; }
  ForwardedBlocked(const ForwardedBlocked&) = delete;
  ForwardedBlocked& operator=(const ForwardedBlocked&) = delete;

 private:
  sigset_t old_;
  bool restored_ = false;
};

// Registers a child's process group while it lives (kill_child_groups above).
class ChildGroup {
 public:
  explicit ChildGroup(pid_t group) {
    std::lock_guard lock(g_groups_mu);
    for (int i = 0; i < kGroupSlots && slot_ < 0; ++i) {
      pid_t none = 0;
      if (g_groups[i].compare_exchange_strong(none, group)) slot_ = i;
    }
    if (g_running++ == 0) {
      struct sigaction a {};
      a.sa_handler = kill_child_groups;
      sigemptyset(&a.sa_mask);
      for (int i = 0; i < 3; ++i) {
        ::sigaction(kForwarded[i], nullptr, &g_previous[i]);
        g_installed[i] = g_previous[i].sa_handler != SIG_IGN;
        if (g_installed[i]) ::sigaction(kForwarded[i], &a, nullptr);
      }
    }
  }
  ~ChildGroup() {
    std::lock_guard lock(g_groups_mu);
    if (slot_ >= 0) g_groups[slot_].store(0);
    if (--g_running == 0)
      for (int i = 0; i < 3; ++i)
        if (g_installed[i]) ::sigaction(kForwarded[i], &g_previous[i], nullptr);
  }
  ChildGroup(const ChildGroup&) = delete;
  ChildGroup& operator=(const ChildGroup&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace

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
  ForwardedBlocked blocked;
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": fork failed");
  if (pid == 0) {  // only async-signal-safe calls from here on
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(126);
    ::setpgid(0, 0);
    ::pthread_sigmask(SIG_SETMASK, &blocked.old(), nullptr);
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
  const ChildGroup group(pid);
  blocked.restore();
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
