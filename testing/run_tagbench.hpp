#pragma once
// Shared by the command-line tests: run the built `tagbench` (TAGBENCH_BIN, a compile definition set
// by tagbench_add_test) with stdout and stderr captured through files, stdin from /dev/null.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace tagbench::testing {

struct CommandResult {
  int code = -1;  // exit status; 128 + signal when killed
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The lines of a text (no line terminators).
inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// A shell word: single-quoted, inner quotes escaped.
inline std::string shell_quote(const std::string& s) {
  std::string r = "'";
  for (const char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

#ifdef TAGBENCH_BIN  // tests that run the program: tagbench_add_test(... NEEDS_CLI)
// `tagbench ARGS`, its output captured in files inside `dir` (which must exist).
inline CommandResult run_tagbench(const std::string& args, const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout", err = dir / "stderr";
  // Appended piece by piece: GCC 12 at -O1 reports a false -Warray-bounds inside std::string for a
  // chain of operator+ (shown through the tests' precompiled header).
  std::string cmd = TAGBENCH_BIN;
  cmd += ' ';
  cmd += args;
  cmd += " >" + shell_quote(out.string());
  cmd += " 2>" + shell_quote(err.string());
  cmd += " </dev/null";
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st), slurp(out), slurp(err)};
}
#endif

}  // namespace tagbench::testing
