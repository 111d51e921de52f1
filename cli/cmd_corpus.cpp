// tagbench corpus: the natural-image corpus for the false-positive experiments (issue 5).
#include <cstdio>
#include <filesystem>
#include <string>

#include "build.hpp"
#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "scan.hpp"
#include "util/sysinfo.hpp"

namespace tagbench::cli {

namespace {
constexpr const char* kHelp = R"(usage: tagbench corpus build [options]
       tagbench corpus list --from DIR

build: the default natural-image corpus from the Debian packages named in the lists
(corpus_tools/data/photo_sources.tsv, video_sources.tsv): apt-get download PKG=VERSION into the
cache (skipped when the .deb is there), dpkg-deb -x into a temporary folder (nothing installed),
the listed files (and those inside gcompris' Qt resource bundles, /_rcc/...), decoded, scaled to
at most 2048 px on the long side, written as PNG:
  DIR/stills/GROUP/NAME.png, DIR/video/GROUP/NAME_fFRAME.png (every frame_step-th frame)
  DIR/manifest.tsv  file, group, package, version, path, licence, sha256 of the extracted original,
                    kind (still | video-frame), frame index
A rebuild with everything in place does nothing; an extracted file whose sha256 differs from the
manifest's is an error naming it and its package.
  --out DIR         the corpus folder (default corpus)
  --lists DIR       folder with photo_sources.tsv / video_sources.tsv (default: the shipped lists)
  --cache DIR       where downloaded .deb files are kept (default DIR/.debs)
  --debs DIR        take PKG_VERSION_*.deb from DIR instead of downloading (offline, tests)
  --packages LIST   only these packages (comma-separated)
  --jobs N          packages processed at once (default: all cores)
  --verify          unpack packages already in place too and check their files' sha256

list: every image under DIR, recursively, as TSV on stdout (status, file, width, height, reason);
unreadable files are listed with the reason and counted, not fatal. A summary goes to stderr.
)";

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (const char c : s + ",") {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  return out;
}

std::string field(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

int corpus_build(const Words& w) {
  const Args a(w, {{"out"}, {"lists"}, {"cache"}, {"debs"}, {"packages"}, {"jobs"}, {"verify", false}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  corpus::BuildOptions o;
  o.out = a.get_or("out", "corpus");
  if (auto v = a.get("lists")) {
    o.lists = *v;
    if (!std::filesystem::is_directory(o.lists)) throw UsageError("--lists " + *v + ": no such directory");
  }
  if (auto v = a.get("cache")) o.cache = *v;
  if (auto v = a.get("debs")) {
    o.debs = *v;
    if (!std::filesystem::is_directory(o.debs)) throw UsageError("--debs " + *v + ": no such directory");
  }
  if (auto v = a.get("packages")) {
    o.packages = split_commas(*v);
    if (o.packages.empty()) throw UsageError("--packages: empty list");
  }
  o.jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  o.verify = a.flag("verify");
  const auto s = corpus::build_corpus(o);
  std::fprintf(stderr,
               "tagbench corpus build: %d packages built, %d already in place; %ld stills, %ld video frames "
               "written in %s (%.1f s)\n",
               s.packages_done, s.packages_skipped, s.stills, s.video_frames, o.out.string().c_str(), s.seconds);
  return 0;
}

int corpus_list(const Words& w) {
  const Args a(w, {{"from"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto from = a.get("from");
  if (!from) throw UsageError("--from DIR is required");
  if (!std::filesystem::is_directory(*from)) throw UsageError("--from " + *from + ": no such directory");
  const auto scan = corpus::scan_folder(*from);
  std::printf("status\tfile\twidth\theight\treason\n");
  for (const auto& i : scan.images)
    std::printf("ok\t%s\t%d\t%d\t\n", field(i.file.string()).c_str(), i.width, i.height);
  for (const auto& u : scan.unreadable)
    std::printf("unreadable\t%s\t\t\t%s\n", field(u.file.string()).c_str(), field(u.reason).c_str());
  std::fprintf(stderr, "tagbench corpus list: %zu images, %zu unreadable, %zu other files in %s\n", scan.images.size(),
               scan.unreadable.size(), scan.other_files, from->c_str());
  return 0;
}
}  // namespace

int cmd_corpus(const Words& w) {
  if (w.empty() || w[0] == "--help" || w[0] == "-h") {
    std::fputs(kHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  if (wants_help(w, kHelp)) return 0;
  const Words rest(w.begin() + 1, w.end());
  if (w[0] == "build") return corpus_build(rest);
  if (w[0] == "list") return corpus_list(rest);
  throw UsageError("unknown subcommand '" + w[0] + "' (build, list)");
}

}  // namespace tagbench::cli
