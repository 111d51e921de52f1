// build_corpus (build.hpp): the lists read, the output names chosen, the packages to process planned,
// what killed runs left cleared, the packages run on worker threads, and the manifest rows no list row
// names pruned with their files. The per-package work (download, unpack, PNGs) is build_packages.cpp.
#include "build.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "build_detail.hpp"
#include "sha256.hpp"
#include "sources.hpp"
#include "tools/atomic_file.hpp"
#include "tools/progress.hpp"

namespace tagbench::corpus {

namespace fs = std::filesystem;

using namespace build_detail;

namespace {

// A manifest file name we may delete: relative, inside stills/ or video/, without "..".
bool prunable_file(const std::string& file) {
  const fs::path p(file);
  if (p.empty() || p.is_absolute()) return false;
  for (const auto& part : p)
    if (part == "..") return false;
  const std::string top = p.begin()->string();
  return top == "stills" || top == "video";
}

// What a run killed with kill -9 leaves: the unpacked packages in OUT/.work (a rerun unpacks every
// package it needs afresh; one build at a time per folder), the temporaries of atomic writes (PNGs,
// the manifest) anywhere in OUT, and its unfinished downloads in the cache. Downloads of a run still
// going (its own process, on this host or another sharing the cache) are left alone.
void clear_leftovers(const fs::path& out, const fs::path& cache) {
  std::error_code ec;
  fs::remove_all(out / ".work", ec);
  remove_stale_temporaries(out, /*recursive=*/true);
  if (cache.empty()) return;
  for (fs::directory_iterator it(cache, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.rfind(kDownloadPrefix, 0) != 0) continue;
    const std::string rest = n.substr(std::string(kDownloadPrefix).size());  // PID-HOST-package
    std::error_code rec;
    if (owner_prefix_is_gone(rest)) fs::remove_all(it->path(), rec);
  }
  remove_stale_temporaries(cache);
}

}  // namespace

BuildStats build_corpus(const BuildOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto sources = load_sources(opt.lists.empty() ? default_lists_dir() : opt.lists);
  fs::create_directories(opt.out);

  Builder b{opt, sources, {}, {}, {}, {}, {}, {}, 0, 0, std::chrono::steady_clock::now(), {}};
  // Output names: the file's stem, or stem-<8 hex of the path's sha256> where a group has two alike.
  std::map<std::pair<std::string, std::string>, int> uses;
  std::vector<std::string> stems;
  for (const auto& s : sources) {
    stems.push_back(sanitize(fs::path(s.path).stem().string()));
    ++uses[{s.group, stems.back()}];
  }
  for (std::size_t i = 0; i < sources.size(); ++i)
    b.out_names.push_back(uses[{sources[i].group, stems[i]}] > 1 ? stems[i] + "-" + sha256_hex(sources[i].path).substr(0, 8)
                                                                 : stems[i]);

  const fs::path manifest_file = opt.out / "manifest.tsv";
  if (fs::exists(manifest_file)) b.manifest = parse_manifest(read_file(manifest_file), manifest_file.string());
  for (const auto& m : b.manifest) b.old_sha[{m.package, m.path}] = m.sha256;

  // Packages in list order, each with its rows.
  std::vector<Package> packages;
  const std::set<std::string> only(opt.packages.begin(), opt.packages.end());
  std::set<std::string> known;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const Source& s = sources[i];
    known.insert(s.package);
    if (!only.empty() && !only.count(s.package)) continue;
    auto it = std::find_if(packages.begin(), packages.end(),
                           [&](const Package& p) { return p.name == s.package && p.version == s.version; });
    if (it == packages.end()) {
      packages.push_back({s.package, s.version, {}});
      it = packages.end() - 1;
    }
    it->rows.push_back(i);
    ++b.rows_total;
  }
  for (const auto& p : only)
    if (!known.count(p)) throw std::runtime_error("--packages: '" + p + "' is not in the lists");

  b.cache = opt.cache.empty() ? opt.out / ".debs" : opt.cache;
  if (opt.debs.empty()) fs::create_directories(b.cache);
  clear_leftovers(opt.out, opt.debs.empty() ? b.cache : fs::path());
  if (opt.progress) b.bar = std::make_unique<ProgressBar>("corpus build");

  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::string error;
  auto worker = [&] {
    while (!failed) {
      const std::size_t k = next++;
      if (k >= packages.size()) return;
      const Package& p = packages[k];
      try {
        if (!opt.verify && b.in_place(p)) {
          std::lock_guard lk(b.mu);
          ++b.stats.packages_skipped;
          b.tick(p.rows.size(), p.name + " in place");
          continue;
        }
        auto rows = b.process(p);
        std::lock_guard lk(b.mu);
        std::erase_if(b.manifest, [&](const ManifestRow& m) { return m.package == p.name; });
        b.manifest.insert(b.manifest.end(), rows.begin(), rows.end());
        b.save_manifest();
        ++b.stats.packages_done;
      } catch (const std::exception& e) {
        std::lock_guard lk(b.mu);
        if (!failed.exchange(true)) error = e.what();
      }
    }
  };
  const int jobs = std::max(1, std::min<int>(opt.jobs, static_cast<int>(packages.size())));
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  b.bar.reset();
  std::error_code ec;
  fs::remove(opt.out / ".work", ec);  // only if empty
  if (failed) throw std::runtime_error(error);
  if (only.empty()) {
    // Rows no list row names: the manifest first (a run killed in between leaves stray files that
    // no row lists, never a row without its file), then their files.
    std::lock_guard lk(b.mu);
    std::vector<ManifestRow> kept, stale;
    for (auto& m : b.manifest) {
      const bool current =
          std::any_of(sources.begin(), sources.end(), [&](const Source& s) { return row_of_source(m, s); });
      (current ? kept : stale).push_back(std::move(m));
    }
    b.manifest = std::move(kept);
    if (!stale.empty()) {
      b.save_manifest();
      std::set<std::string> in_use;
      for (const auto& m : b.manifest) in_use.insert(m.file);
      for (const auto& m : stale) {
        if (in_use.count(m.file) || !prunable_file(m.file)) continue;
        fs::remove(opt.out / m.file, ec);
        fs::remove((opt.out / m.file).parent_path(), ec);  // the group's folder, once empty
      }
      b.stats.rows_pruned = static_cast<long>(stale.size());
    }
  }
  if (!fs::exists(manifest_file)) {
    std::lock_guard lk(b.mu);
    b.save_manifest();
  }
  b.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b.stats;
}

}  // namespace tagbench::corpus
