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

}  // namespace tagbench
