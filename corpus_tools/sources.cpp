#include "sources.hpp"

#include <map>
#include <sstream>
#include <stdexcept>

#include "tools/atomic_file.hpp"

namespace tagbench::corpus {

namespace {
std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t tab = line.find('\t', start);
    out.push_back(line.substr(start, tab - start));
    if (tab == std::string::npos) break;
    start = tab + 1;
  }
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    out.push_back(line);
  }
  return out;
}

bool has_bad_char(const std::string& s) { return s.find_first_of("\t\n\r") != std::string::npos; }
}  // namespace

std::vector<Source> parse_sources(const std::string& text, const std::string& name) {
  const auto lines = lines_of(text);
  if (lines.empty()) throw std::runtime_error(name + ": empty list (no header)");
  const auto header = split_tabs(lines[0]);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* c : {"group", "debian_package", "version", "path_in_package", "license"})
    if (!col.count(c)) throw std::runtime_error(name + ":1: no column '" + c + "'");
  const bool video = col.count("frame_step") > 0;
  std::vector<Source> out;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const std::string where = name + ":" + std::to_string(i + 1) + ": ";
    const auto f = split_tabs(lines[i]);
    if (f.size() != header.size())
      throw std::runtime_error(where + std::to_string(f.size()) + " columns, the header has " +
                               std::to_string(header.size()));
    Source s{f[col["group"]], f[col["debian_package"]], f[col["version"]], f[col["path_in_package"]],
             f[col["license"]], 0};
    if (s.group.empty() || s.package.empty() || s.version.empty() || s.path.empty())
      throw std::runtime_error(where + "empty group, package, version or path");
    if (s.path[0] != '/') throw std::runtime_error(where + "path '" + s.path + "' is not absolute");
    if (s.path.find("/../") != std::string::npos || s.group.find('/') != std::string::npos || s.group[0] == '.')
      throw std::runtime_error(where + "group or path escapes its folder");
    if (video) {
      const std::string& fs = f[col["frame_step"]];
      std::size_t used = 0;
      int step = 0;
      try {
        step = std::stoi(fs, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != fs.size() || fs.empty() || step < 1)
        throw std::runtime_error(where + "frame_step '" + fs + "' is not a positive integer");
      s.frame_step = step;
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<Source> load_sources(const std::filesystem::path& dir) {
  std::vector<Source> out;
  bool any = false;
  for (const char* f : {"photo_sources.tsv", "video_sources.tsv"}) {
    const auto p = dir / f;
    if (!std::filesystem::exists(p)) continue;
    any = true;
    for (auto& s : parse_sources(read_file(p), p.string())) out.push_back(std::move(s));
  }
  if (!any) throw std::runtime_error(dir.string() + ": neither photo_sources.tsv nor video_sources.tsv");
  return out;
}

std::filesystem::path default_lists_dir() { return TAGBENCH_CORPUS_LISTS; }

namespace {
constexpr const char* kManifestHeader = "file\tgroup\tpackage\tversion\tpath\tlicence\tsha256\tkind\tframe";
}

std::string manifest_tsv(const std::vector<ManifestRow>& rows) {
  std::string out = std::string(kManifestHeader) + "\n";
  for (const auto& r : rows) {
    for (const auto* s : {&r.file, &r.group, &r.package, &r.version, &r.path, &r.licence, &r.sha256, &r.kind})
      if (has_bad_char(*s)) throw std::runtime_error("manifest: a field of " + r.file + " contains a tab or newline");
    out += r.file + "\t" + r.group + "\t" + r.package + "\t" + r.version + "\t" + r.path + "\t" + r.licence + "\t" +
           r.sha256 + "\t" + r.kind + "\t" + (r.frame >= 0 ? std::to_string(r.frame) : std::string()) + "\n";
  }
  return out;
}

std::vector<ManifestRow> parse_manifest(const std::string& text, const std::string& name) {
  const auto lines = lines_of(text);
  if (lines.empty() || lines[0] != kManifestHeader) throw std::runtime_error(name + ":1: not a corpus manifest header");
  std::vector<ManifestRow> out;
  std::map<std::string, std::size_t> line_of;  // file -> its line: a file listed twice would be counted twice
  for (std::size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const std::string where = name + ":" + std::to_string(i + 1) + ": ";
    const auto f = split_tabs(lines[i]);
    if (f.size() != 9) throw std::runtime_error(where + std::to_string(f.size()) + " columns, expected 9");
    ManifestRow r{f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], -1};
    if (r.kind != "still" && r.kind != "video-frame") throw std::runtime_error(where + "kind '" + r.kind + "'");
    if (r.sha256.size() != 64 || r.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
      throw std::runtime_error(where + "bad sha256 '" + r.sha256 + "'");
    if (r.file.empty() || r.file[0] == '/' || r.file.find("..") != std::string::npos)
      throw std::runtime_error(where + "file '" + r.file + "' is not a relative path inside the corpus");
    if (!f[8].empty()) {
      std::size_t used = 0;
      try {
        r.frame = std::stol(f[8], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != f[8].size() || r.frame < 0) throw std::runtime_error(where + "bad frame index '" + f[8] + "'");
    }
    if ((r.kind == "video-frame") != (r.frame >= 0))
      throw std::runtime_error(where + "a video frame needs a frame index and a still none");
    if (const auto [it, fresh] = line_of.emplace(r.file, i + 1); !fresh)
      throw std::runtime_error(where + "file '" + r.file + "' is already on line " + std::to_string(it->second));
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace tagbench::corpus
