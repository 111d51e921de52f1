#pragma once
// A user's own folder of images (LabelMe, COCO, ...), walked recursively. A file is an image file
// when it has an image extension or OpenCV recognises its signature; one with an image extension
// whose signature no decoder recognises, or that cannot be opened, is unreadable (listed with the
// reason and counted, never fatal). Other files are counted and skipped.
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

// The image files without decoding them (only their first bytes are read, for the signature):
// width and height are 0. Cheap enough for every shard of a big folder to list it. Throws
// std::runtime_error only if `dir` itself is not a readable folder.
FolderScan list_image_files(const std::filesystem::path& dir);

// list_image_files, then every image decoded (its width and height filled in); those that do not
// decode (a truncated file, say) move to `unreadable`. Throws as list_image_files.
FolderScan scan_folder(const std::filesystem::path& dir);

}  // namespace tagbench::corpus
