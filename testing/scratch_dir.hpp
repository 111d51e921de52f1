#pragma once
// A fresh scratch folder for a test (mkdtemp under the system's temp folder), removed with all its
// contents when the object goes out of scope, so no test leaves files behind or meets a stale one.
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace tagbench::testing {

class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix = "tagbench_test") {
    std::string t = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp " + t + " failed");
    path_ = t;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& p) const { return path_ / p; }

 private:
  std::filesystem::path path_;
};

}  // namespace tagbench::testing

namespace tagbench::testing {

// One scratch folder for the whole test program, made on first use and removed at exit (a static
// ScratchDir): for tests that share files between test cases.
inline const std::filesystem::path& program_scratch(const std::string& prefix) {
  static const ScratchDir dir(prefix);
  return dir.path();
}

}  // namespace tagbench::testing
