#pragma once
// A user's own folder of images (LabelMe, COCO, ...), walked recursively. Every file that looks
// like an image (by extension or by OpenCV recognising its signature) is decoded; those that fail
// are listed with the reason and counted, never fatal. Other files are counted and skipped.
#include <filesystem>
#include <string>
#include <vector>

namespace tagbench::corpus {

struct ScannedImage {
  std::filesystem::path file;
  int width = 0, height = 0;
};
struct UnreadableFile {
  std::filesystem::path file;
  std::string reason;
};
struct FolderScan {
  std::vector<ScannedImage> images;        // sorted by path
  std::vector<UnreadableFile> unreadable;  // sorted by path
  std::size_t other_files = 0;             // not images (by extension and signature)
};

// Throws std::runtime_error only if `dir` itself is not a readable folder.
FolderScan scan_folder(const std::filesystem::path& dir);

}  // namespace tagbench::corpus
