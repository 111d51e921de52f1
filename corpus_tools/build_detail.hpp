#pragma once
// What build.cpp (build_corpus: the package plan, leftovers, pruning) and build_packages.cpp (the
// per-package download, unpack and conversion) share and nothing else needs: the download folders'
// prefix, output-name and manifest-row helpers, and the Builder that build_corpus drives.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "build.hpp"
#include "sources.hpp"
#include "tools/progress.hpp"

namespace tagbench::corpus::build_detail {

inline constexpr const char* kDownloadPrefix = ".download-";  // + owner_tag() + "-" + package: one download

std::string sanitize(const std::string& s);

// Whether manifest row m came from list row s: same package, version and group, and the row's
// file inside the package is the source's path (or matches it, for a folder of frames).
bool row_of_source(const ManifestRow& m, const Source& s);

struct Package {
  std::string name, version;
  std::vector<std::size_t> rows;  // indices into the sources
};

struct Builder {
  const BuildOptions& opt;
  const std::vector<Source>& sources;
  std::vector<std::string> out_names;  // per source: the file stem for its outputs
  std::map<std::pair<std::string, std::string>, std::string> old_sha;  // (package, path) -> sha256
  std::vector<ManifestRow> manifest;
  std::filesystem::path cache;
  std::mutex mu;
  std::unique_ptr<ProgressBar> bar;
  std::size_t rows_total = 0, rows_done = 0;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  BuildStats stats;

  void tick(std::size_t n, const std::string& what);  // under mu
  std::filesystem::path obtain_deb(const Package& p);
  void check_sha(const Package& p, const std::string& path, const std::string& sha);
  std::string write_png(const cv::Mat& img, const std::filesystem::path& rel, const std::string& what);
  // Everything this package's list rows need is in the manifest and on disk.
  bool in_place(const Package& p);
  std::vector<ManifestRow> process(const Package& p);
  void save_manifest();  // under mu
};

}  // namespace tagbench::corpus::build_detail
