#pragma once
// Shared by the bad-input matrix's two halves: test_bad_input_matrix.cpp runs each case and checks
// what it left, test_bad_input_cases.cpp holds the table of cases. A case, the limits its child
// process runs under, and that child run (also used by a case's setup).
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace test_bad_input {

namespace fs = std::filesystem;

// ---- the child process --------------------------------------------------------------------------

struct Limits {
  long long fsize = 0;      // > 0: RLIMIT_FSIZE in bytes (a full disk)
  const char* path = nullptr;  // non-null: PATH, relative to the scratch folder (e.g. an empty folder)
};

struct ChildRun {
  int status = 0;
  bool timed_out = false;
  std::string out, err;
};

// Runs `tagbench args` in `cwd` with stdin from /dev/null and stdout/stderr read through pipes.
ChildRun run_child(const fs::path& cwd, const std::vector<std::string>& args, const Limits& lim);

// ---- the table ----------------------------------------------------------------------------------

using Setup = std::function<void(const fs::path& dir)>;

struct Case {
  std::string name;
  Setup setup;
  std::vector<std::string> args;
  int code;
  std::vector<std::string> expect;  // in stderr (an error) or stdout (exit 0)
  Limits limits{};
};

inline std::ostream& operator<<(std::ostream& o, const Case& c) { return o << c.name; }

// The table (test_bad_input_cases.cpp).
const std::vector<Case>& cases();

}  // namespace test_bad_input
