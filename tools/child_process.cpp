#include "tools/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
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

}  // namespace tagbench
