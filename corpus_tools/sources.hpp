#pragma once
// The corpus definition (photo_sources.tsv, video_sources.tsv) and the built corpus's manifest.tsv.
#include <filesystem>
#include <string>
#include <vector>

namespace tagbench::corpus {

// One row of the lists: a still (frame_step 0) or a clip / folder of frames (frame_step >= 1).
// A path starting with "/_rcc/" names a file inside a Qt resource bundle of gcompris-qt-data; a
// path with '*' in its last component is a folder of frames (sorted by name).
struct Source {
  std::string group, package, version, path, licence;
  int frame_step = 0;
  bool is_video() const { return frame_step > 0; }
};

// Parses a list; `name` for errors. Columns by header: group, debian_package, version,
// path_in_package, [frame_step,] license. Throws std::runtime_error "NAME:LINE: problem".
std::vector<Source> parse_sources(const std::string& text, const std::string& name);
// photo_sources.tsv then video_sources.tsv from `dir` (either may be absent, not both).
std::vector<Source> load_sources(const std::filesystem::path& dir);
// The lists shipped with the program (corpus_tools/data).
std::filesystem::path default_lists_dir();

struct ManifestRow {
  std::string file;     // relative to the corpus folder, e.g. stills/cimg-postcards/postcard1.png
  std::string group, package, version;
  std::string path;     // the extracted original inside the package (a frame folder's actual file)
  std::string licence;
  std::string sha256;   // of the extracted original (the whole clip for video frames)
  std::string kind;     // "still" or "video-frame"
  long frame = -1;      // frame index within the clip or folder; -1 (written empty) for stills
  bool operator==(const ManifestRow&) const = default;
};

std::string manifest_tsv(const std::vector<ManifestRow>& rows);
std::vector<ManifestRow> parse_manifest(const std::string& text, const std::string& name);

}  // namespace tagbench::corpus
