#include "scan.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

namespace tagbench::corpus {

namespace {
bool image_extension(const std::filesystem::path& p) {
  static const std::set<std::string> kExt = {".jpg", ".jpeg", ".jpe", ".png", ".webp", ".bmp", ".dib", ".tif",
                                             ".tiff", ".pgm", ".ppm", ".pbm", ".pnm", ".pxm", ".jp2", ".sr",
                                             ".ras", ".exr", ".hdr", ".pic", ".gif"};
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return kExt.count(e) > 0;
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return s.substr(0, 200);
}

// cv::haveImageReader reads only the signature bytes; imread finds its decoder the same way, so a
// file it refuses would not decode either.
bool has_image_signature(const std::filesystem::path& f) {
  try {
    return cv::haveImageReader(f.string());
  } catch (const cv::Exception&) {
    return false;
  }
}
}  // namespace

FolderScan list_image_files(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw std::runtime_error(dir.string() + ": not a folder");
  std::vector<fs::path> files;
  FolderScan out;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) throw std::runtime_error(dir.string() + ": cannot read: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) {
      out.unreadable.push_back({it->path(), "cannot list: " + ec.message()});
      ec.clear();
      continue;
    }
    std::error_code fe;
    if (it->is_regular_file(fe)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const bool by_extension = image_extension(f);
    if (!std::ifstream(f, std::ios::binary)) {  // unknown whether it is an image: listed, not skipped
      out.unreadable.push_back({f, "cannot open"});
      continue;
    }
    const bool signature = has_image_signature(f);
    if (signature) out.images.push_back({f, 0, 0});
    else if (by_extension) out.unreadable.push_back({f, "not decodable as an image"});
    else ++out.other_files;
  }
  std::sort(out.unreadable.begin(), out.unreadable.end(),
            [](const UnreadableFile& a, const UnreadableFile& b) { return a.file < b.file; });
  return out;
}

FolderScan scan_folder(const std::filesystem::path& dir) {
  FolderScan listed = list_image_files(dir);
  FolderScan out;
  out.unreadable = std::move(listed.unreadable);
  out.other_files = listed.other_files;
  for (const auto& img : listed.images) {
    cv::Mat m;
    try {
      m = cv::imread(img.file.string(), cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception& e) {
      out.unreadable.push_back({img.file, "OpenCV: " + one_line(e.what())});
      continue;
    }
    if (m.empty()) {
      std::ifstream probe(img.file, std::ios::binary);
      out.unreadable.push_back({img.file, probe ? "not decodable as an image" : "cannot open"});
      continue;
    }
    out.images.push_back({img.file, m.cols, m.rows});
  }
  std::sort(out.unreadable.begin(), out.unreadable.end(),
            [](const UnreadableFile& a, const UnreadableFile& b) { return a.file < b.file; });
  return out;
}

}  // namespace tagbench::corpus
