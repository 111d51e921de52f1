#pragma once
// Running another program (apt-get, dpkg-deb, povray) and waiting for it.
#include <filesystem>
#include <string>
#include <vector>

namespace tagbench {

// How a child ended: its exit code, or the signal that killed it.
struct ChildStatus {
  int exit_code = 0;  // 126: it could not be set up (log, folder), 127: the program could not be run
  int signal = 0;     // non-zero when a signal ended it
  bool timed_out = false;  // run_child_io: killed (SIGKILL) because it ran past its time limit
  // The shell's convention: the exit code, or 128 + the signal.
  int code() const { return signal != 0 ? 128 + signal : exit_code; }
};

// Runs argv (argv[0] looked up in PATH unless it holds a slash) in the folder `cwd`, stdin from
// /dev/null, stdout and stderr into `log` (created or emptied; a relative path is taken from our
// own folder, not from `cwd`), at `nice_increment` lower priority; waits for it. The child dies
// with the thread that started it (PR_SET_PDEATHSIG): after a kill -9 no orphan goes on writing
// into folders a rerun uses. Throws std::runtime_error only when it cannot start or wait.
ChildStatus run_child(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                      const std::filesystem::path& log, int nice_increment = 0);

// The files a child reads and writes (all three required; stdout and stderr created or emptied), and
// how long it may run.
struct ChildIo {
  std::filesystem::path stdin_file, stdout_file, stderr_file;
  double timeout_seconds = 0;  // > 0: past it the child and its process group are killed (SIGKILL)
};

// As run_child, with stdin, stdout and stderr from and into files, in a process group of its own
// (so a timeout also ends what it started), and a time limit. While it runs, SIGINT, SIGTERM or SIGHUP
// to this process first kill the child's whole process group (which a Ctrl-C at the terminal does
// not reach), then take their earlier course.
ChildStatus run_child_io(const std::vector<std::string>& argv, const std::filesystem::path& cwd, const ChildIo& io);

}  // namespace tagbench
