// The per-package work of build_corpus (build.hpp): the .deb found in --debs or the cache or fetched
// with apt-get download, unpacked with dpkg-deb -x, and its listed files (loose, inside a Qt resource
// bundle, a folder of frames or a clip) checked against the manifest's sha256 and written as PNGs,
// with the progress. build.cpp plans the packages and runs these Builder steps on its workers.
#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "build.hpp"
#include "build_detail.hpp"
#include "rcc.hpp"
#include "sha256.hpp"
#include "tools/atomic_file.hpp"
#include "tools/child_process.hpp"
#include "tools/progress.hpp"

namespace tagbench::corpus {

namespace fs = std::filesystem;

std::string deb_file_prefix(const std::string& package, const std::string& version) {
  std::string v;
  for (const char c : version) v += c == ':' ? std::string("%3a") : std::string(1, c);
  return package + "_" + v + "_";
}

namespace {

constexpr const char* kRccPrefix = "/_rcc/";
constexpr const char* kRccDir = "usr/share/gcompris-qt/rcc";

bool is_rcc(const std::string& path) { return path.rfind(kRccPrefix, 0) == 0; }
bool is_glob(const std::string& path) {
  return fs::path(path).filename().string().find_first_of("*?[") != std::string::npos;
}

std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last.empty() ? "(no output)" : last;
}

std::optional<fs::path> find_deb(const fs::path& dir, const std::string& prefix) {
  std::error_code ec;
  std::vector<fs::path> hits;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    if (n.rfind(prefix, 0) == 0 && n.size() > 4 && n.compare(n.size() - 4, 4, ".deb") == 0 &&
        it->is_regular_file())
      hits.push_back(it->path());
  }
  if (hits.empty()) return std::nullopt;
  std::sort(hits.begin(), hits.end());
  return hits.front();
}

// Removes a folder and all in it when it goes out of scope, however the scope is left (best effort).
struct RemoveOnExit {
  fs::path dir;
  ~RemoveOnExit() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

namespace build_detail {

std::string sanitize(const std::string& s) {
  std::string out;
  for (const char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  return out.empty() ? "_" : out;
}

bool row_of_source(const ManifestRow& m, const Source& s) {
  if (m.package != s.package || m.version != s.version || m.group != s.group) return false;
  return is_glob(s.path) ? ::fnmatch(s.path.c_str(), m.path.c_str(), FNM_PATHNAME) == 0 : m.path == s.path;
}

void Builder::tick(std::size_t n, const std::string& what) {  // under mu
  rows_done += n;
  if (!bar) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double frac = rows_total ? static_cast<double>(rows_done) / static_cast<double>(rows_total) : 1.0;
  bar->update(frac, std::to_string(rows_done) + "/" + std::to_string(rows_total) + " sources", what,
              frac > 0 ? el * (1 - frac) / frac : 0);
}

fs::path Builder::obtain_deb(const Package& p) {
  const std::string prefix = deb_file_prefix(p.name, p.version);
  if (!opt.debs.empty()) {
    if (auto d = find_deb(opt.debs, prefix)) return *d;
    throw std::runtime_error("no " + prefix + "*.deb in " + opt.debs.string() + " (--debs)");
  }
  if (auto d = find_deb(cache, prefix)) return *d;
  // Downloaded into a folder of its own and moved into the cache once complete: a download cut
  // short (kill -9) must never be a PKG_VERSION_*.deb that a rerun takes as the package.
  const fs::path dl = cache / (std::string(kDownloadPrefix) + owner_tag() + "-" + sanitize(p.name));
  fs::remove_all(dl);
  fs::create_directories(dl);
  const RemoveOnExit cleanup{dl};
  const fs::path log = dl / "apt-get.log";
  const int rc = run_child({"apt-get", "download", "-q", p.name + "=" + p.version}, dl, log).code();
  if (rc != 0)
    throw std::runtime_error("apt-get download " + p.name + "=" + p.version + " failed (exit " + std::to_string(rc) +
                             "): " + last_line(log));
  const auto got = find_deb(dl, prefix);
  if (!got)
    throw std::runtime_error("apt-get download " + p.name + "=" + p.version + " left no " + prefix + "*.deb in " +
                             dl.string());
  const fs::path deb = cache / got->filename();
  fs::rename(*got, deb);
  return deb;
}

void Builder::check_sha(const Package& p, const std::string& path, const std::string& sha) {
  std::lock_guard lk(mu);
  const auto it = old_sha.find({p.name, path});
  if (it != old_sha.end() && it->second != sha)
    throw std::runtime_error(path + " in package " + p.name + " " + p.version + " changed: sha256 " + sha +
                             ", the manifest has " + it->second + " (remove " + (opt.out / "manifest.tsv").string() +
                             " to accept the new file)");
}

std::string Builder::write_png(const cv::Mat& img, const fs::path& rel, const std::string& what) {
  cv::Mat m = img;
  const int side = std::max(m.cols, m.rows);
  if (side > opt.max_side) {
    const double s = static_cast<double>(opt.max_side) / side;
    const cv::Size size(std::max(1, static_cast<int>(std::lround(m.cols * s))),
                        std::max(1, static_cast<int>(std::lround(m.rows * s))));
    cv::resize(img, m, size, 0, 0, cv::INTER_AREA);
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", m, png)) throw std::runtime_error(what + ": PNG encoding failed");
  fs::create_directories((opt.out / rel).parent_path());
  write_file_atomic(opt.out / rel, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  return rel.generic_string();
}

bool Builder::in_place(const Package& p) {
  std::lock_guard lk(mu);
  for (const std::size_t i : p.rows) {
    const Source& s = sources[i];
    bool found = false;
    for (const auto& m : manifest) {
      if (!row_of_source(m, s)) continue;
      if (!fs::exists(opt.out / m.file)) return false;
      found = true;
    }
    if (!found) return false;
  }
  return true;
}

std::vector<ManifestRow> Builder::process(const Package& p) {
  const fs::path deb = obtain_deb(p);
  const fs::path tmp = opt.out / ".work" / sanitize(p.name);
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const RemoveOnExit cleanup{tmp};
  const fs::path log = opt.out / ".work" / (sanitize(p.name) + ".log");
  const int rc =
      run_child({"dpkg-deb", "-x", fs::absolute(deb).string(), fs::absolute(tmp).string()}, ".", log).code();
  if (rc != 0)
    throw std::runtime_error("dpkg-deb -x " + deb.string() + " failed (exit " + std::to_string(rc) +
                             "): " + last_line(log));
  fs::remove(log);

  std::map<fs::path, std::unique_ptr<RccArchive>> bundles;
  auto bundle = [&](const fs::path& f) -> const RccArchive& {
    auto& b = bundles[f];
    if (!b) b = std::make_unique<RccArchive>(RccArchive::open(f));
    return *b;
  };
  auto from_rcc = [&](const std::string& path) {
    const std::string resource = path.substr(std::string(kRccPrefix).size() - 1);  // keeps the leading '/'
    const fs::path dir = tmp / kRccDir;
    std::vector<fs::path> candidates;
    const auto act = resource.find("/activities/");
    if (act != std::string::npos) {
      const auto start = act + 12, end = resource.find('/', start);
      candidates.push_back(dir / (resource.substr(start, end - start) + ".rcc"));
    }
    std::error_code ec;
    std::vector<fs::path> all;
    for (fs::directory_iterator it(dir, ec), e; !ec && it != e; it.increment(ec))
      if (it->path().extension() == ".rcc") all.push_back(it->path());
    std::sort(all.begin(), all.end());
    candidates.insert(candidates.end(), all.begin(), all.end());
    for (const auto& c : candidates) {
      if (!fs::exists(c)) continue;
      if (auto bytes = bundle(c).read(resource)) return std::move(*bytes);
    }
    throw std::runtime_error(path + ": not in any Qt resource bundle of " + p.name + " " + p.version + " (" +
                             dir.string() + ")");
  };
  auto extracted = [&](const std::string& path) {
    const fs::path f = tmp / path.substr(1);
    if (!fs::is_regular_file(f)) throw std::runtime_error(path + ": not in package " + p.name + " " + p.version);
    return f;
  };

  std::vector<ManifestRow> rows;
  for (const std::size_t i : p.rows) {
    const Source& s = sources[i];
    const std::string who = s.path + " (" + p.name + " " + p.version + ")";
    auto row = [&](const std::string& file, const std::string& path, const std::string& sha, long frame) {
      rows.push_back({file, s.group, s.package, s.version, path, s.licence, sha,
                      frame < 0 ? "still" : "video-frame", frame});
    };
    if (!s.is_video()) {
      const std::string bytes = is_rcc(s.path) ? from_rcc(s.path) : read_file(extracted(s.path));
      const std::string sha = sha256_hex(bytes);
      check_sha(p, s.path, sha);
      const cv::Mat img = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U,
                                               const_cast<char*>(bytes.data())), cv::IMREAD_COLOR);
      if (img.empty()) throw std::runtime_error(who + ": OpenCV cannot decode it");
      row(write_png(img, fs::path("stills") / s.group / (out_names[i] + ".png"), who), s.path, sha, -1);
      std::lock_guard lk(mu);
      ++stats.stills;
    } else if (is_glob(s.path)) {
      const fs::path parent = tmp / fs::path(s.path.substr(1)).parent_path();
      std::vector<fs::path> frames;
      std::error_code ec;
      for (fs::directory_iterator it(parent, ec), e; !ec && it != e; it.increment(ec)) {
        const std::string rel = "/" + fs::relative(it->path(), tmp).generic_string();
        if (it->is_regular_file() && ::fnmatch(s.path.c_str(), rel.c_str(), FNM_PATHNAME) == 0)
          frames.push_back(it->path());
      }
      if (frames.empty()) throw std::runtime_error(who + ": no file matches in the package");
      std::sort(frames.begin(), frames.end());
      for (std::size_t k = 0; k < frames.size(); k += static_cast<std::size_t>(s.frame_step)) {
        const std::string path = "/" + fs::relative(frames[k], tmp).generic_string();
        const std::string bytes = read_file(frames[k]);
        const std::string sha = sha256_hex(bytes);
        check_sha(p, path, sha);
        const cv::Mat img = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U,
                                                 const_cast<char*>(bytes.data())), cv::IMREAD_COLOR);
        if (img.empty()) throw std::runtime_error(path + " (" + p.name + "): OpenCV cannot decode it");
        const fs::path rel = fs::path("video") / s.group / (sanitize(frames[k].stem().string()) + ".png");
        row(write_png(img, rel, path), path, sha, static_cast<long>(k));
        std::lock_guard lk(mu);
        ++stats.video_frames;
      }
    } else {
      const fs::path clip = extracted(s.path);
      const std::string sha = sha256_file(clip);
      check_sha(p, s.path, sha);
      cv::VideoCapture cap(clip.string());
      if (!cap.isOpened()) throw std::runtime_error(who + ": OpenCV cannot open the video");
      cv::Mat frame;
      long k = 0, kept = 0;
      while (cap.read(frame)) {
        if (k % s.frame_step == 0) {
          char suffix[32];
          std::snprintf(suffix, sizeof suffix, "_f%06ld.png", k);
          row(write_png(frame, fs::path("video") / s.group / (out_names[i] + suffix), who), s.path, sha, k);
          ++kept;
        }
        ++k;
      }
      if (kept == 0) throw std::runtime_error(who + ": no frame could be decoded");
      std::lock_guard lk(mu);
      stats.video_frames += kept;
    }
    std::lock_guard lk(mu);
    tick(1, p.name);
  }
  return rows;
}

void Builder::save_manifest() {  // under mu
  std::sort(manifest.begin(), manifest.end(),
            [](const ManifestRow& a, const ManifestRow& b) { return a.file < b.file; });
  write_file_atomic(opt.out / "manifest.tsv", manifest_tsv(manifest));
}

}  // namespace build_detail

}  // namespace tagbench::corpus
