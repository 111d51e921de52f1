#include "cli/detect_inputs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

namespace {

const std::set<std::string>& image_extensions() {
  static const std::set<std::string> e = {".png", ".jpg", ".jpeg", ".jpe", ".jp2", ".pgm", ".ppm", ".pbm",
                                          ".pnm", ".pam", ".pfm", ".tif", ".tiff", ".bmp", ".dib", ".webp",
                                          ".exr", ".hdr", ".pic", ".sr", ".ras"};
  return e;
}

const std::set<std::string>& video_extensions() {
  static const std::set<std::string> e = {".mp4", ".avi", ".mkv", ".mov", ".webm", ".m4v", ".mpg",
                                          ".mpeg", ".wmv", ".flv", ".ogv", ".3gp", ".ts", ".mjpeg", ".mjpg"};
  return e;
}

}  // namespace

bool is_video_path(const fs::path& p) { return video_extensions().count(lower(p.extension().string())) > 0; }
bool is_image_path(const fs::path& p) { return image_extensions().count(lower(p.extension().string())) > 0; }

namespace {

std::string system_reason(const std::error_code& ec) { return ec ? ec.message() : std::string("unknown error"); }

}  // namespace

std::vector<Source> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<Source> out;
  for (const std::string& in : inputs) {
    const fs::path p(in);
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    if (ec || !fs::exists(st)) {
      out.push_back({p, in, false, ec && ec != std::errc::no_such_file_or_directory ? system_reason(ec)
                                                                                  : "no such file or directory", {}});
      continue;
    }
    if (fs::is_directory(st)) {
      std::vector<fs::path> files;
      std::error_code it_ec;
      fs::recursive_directory_iterator it(p, fs::directory_options::skip_permission_denied, it_ec), end;
      for (; !it_ec && it != end; it.increment(it_ec)) {
        std::error_code fe;
        if (it->is_regular_file(fe) && is_image_path(it->path())) files.push_back(it->path());
      }
      if (it_ec) {
        out.push_back({p, in, false, "cannot read directory: " + system_reason(it_ec), {}});
        continue;
      }
      if (files.empty()) {
        out.push_back({p, in, false, "directory has no image files", {}});
        continue;
      }
      std::sort(files.begin(), files.end());
      for (const auto& f : files) out.push_back({f, f.string(), false, {}, {}});
      continue;
    }
    out.push_back({p, in, is_video_path(p), {}, {}});
  }
  // Unique output names: the file name without its extension, then _2, _3, ... on a clash.
  std::set<std::string> used;
  for (auto& s : out) {
    if (!s.error.empty()) continue;
    std::string stem = s.path.stem().string();
    if (stem.empty()) stem = "image";
    std::string name = stem;
    for (int k = 2; used.count(name); ++k) name = stem + "_" + std::to_string(k);
    used.insert(name);
    s.out_name = name;
  }
  return out;
}

QuietStderr::QuietStderr() {
  std::fflush(stderr);
  saved_ = ::dup(STDERR_FILENO);
  const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (saved_ < 0 || null < 0 || ::dup2(null, STDERR_FILENO) < 0) {
    if (saved_ >= 0) ::close(saved_);
    saved_ = -1;
  }
  if (null >= 0) ::close(null);
}

QuietStderr::~QuietStderr() {
  if (saved_ < 0) return;
  std::fflush(stderr);
  ::dup2(saved_, STDERR_FILENO);
  ::close(saved_);
}

}  // namespace tagbench::cli::detect_cmd
