#pragma once
// Building the natural-image corpus from the lists: fetch each pinned Debian package (apt-get
// download, or a folder of .deb files), unpack it with dpkg-deb -x into a temporary folder (nothing
// installed), take the listed files (and those inside gcompris' Qt resource bundles), decode them
// with OpenCV, scale to at most 2048 px on the long side and write PNGs:
//   OUT/stills/<group>/<name>.png, OUT/video/<group>/<name>_f<frame>.png, OUT/manifest.tsv.
// A rebuild with every output in place does nothing; an extracted original whose sha256 differs
// from the manifest's is an error naming it and its package. Interrupted (even by kill -9), a rerun
// ends with the files of an uninterrupted build: the manifest is written after each package, every
// file atomically, a download is moved into the cache only when complete, the child processes die
// with the build, and a run first clears what killed runs left (OUT/.work, temporaries, downloads).
// One build at a time per output folder.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sources.hpp"

namespace tagbench::corpus {

struct BuildOptions {
  std::filesystem::path out = "corpus";
  std::filesystem::path lists;       // empty: default_lists_dir()
  std::filesystem::path cache;       // downloaded .deb files; empty: OUT/.debs
  std::filesystem::path debs;        // if set: take PKG_VERSION_*.deb from here instead of apt-get download
  std::vector<std::string> packages; // if set: only these packages
  int jobs = 1;                      // packages processed at once
  int max_side = 2048;
  bool verify = false;               // re-unpack packages already in place and check their sha256
  bool progress = true;              // progress on stderr (a bar when it is a terminal)
};

struct BuildStats {
  int packages_done = 0, packages_skipped = 0;
  long stills = 0, video_frames = 0;
  long rows_pruned = 0;  // manifest rows of sources no longer in the lists, removed with their files
  double seconds = 0;
};

// After a successful build over the whole lists (no `packages` filter), manifest rows that no list
// row names (a source taken out of the lists, or moved to another group or version) are removed, and
// then their files (only files under stills/ or video/ inside OUT that no kept row uses), so the
// corpus the experiments read is the lists' and nothing else.
BuildStats build_corpus(const BuildOptions& opt);

// The file name apt-get download gives PKG=VERSION, up to the architecture: "pkg_1%3a2.0-1_"
// (an epoch's ':' is written %3a).
std::string deb_file_prefix(const std::string& package, const std::string& version);

}  // namespace tagbench::corpus
