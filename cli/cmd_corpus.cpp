// tagbench corpus: the natural-image corpus for the false-positive experiments (issue 5).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "build.hpp"
#include "candidates.hpp"
#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "scan.hpp"
#include "codes/families.hpp"
#include "tools/atomic_file.hpp"
#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

namespace {

// Which of `inputs` writing the store `out` and its index (the same name, .tsv) would replace, if any.
std::optional<std::filesystem::path> replaced_input(const std::filesystem::path& out,
                                                    const std::vector<std::filesystem::path>& inputs) {
  std::error_code ec;
  for (const std::filesystem::path& o : {out, std::filesystem::path(out).replace_extension(".tsv")})
    for (const auto& in : inputs)
      if (std::filesystem::equivalent(o, in, ec)) return in;
  return std::nullopt;
}
constexpr const char* kCorpusHelp = R"(usage: tagbench corpus build [options]
       tagbench corpus list --from DIR
       tagbench corpus candidates --corpus DIR [--shard i/N] [--out FILE] [--jobs N]
       tagbench corpus merge --out FILE SHARD.bin...
       tagbench corpus score --candidates FILE --family F... [--max-bits K]

build: the default natural-image corpus from the Debian packages named in the lists
(corpus_tools/data/photo_sources.tsv, video_sources.tsv): apt-get download PKG=VERSION into the
cache (skipped when the .deb is there), dpkg-deb -x into a temporary folder (nothing installed),
the listed files (and those inside gcompris' Qt resource bundles, /_rcc/...), decoded, scaled to
at most 2048 px on the long side, written as PNG:
  DIR/stills/GROUP/NAME.png, DIR/video/GROUP/NAME_fFRAME.png (every frame_step-th frame)
  DIR/manifest.tsv  file, group, package, version, path, licence, sha256 of the extracted original,
                    kind (still | video-frame), frame index
A rebuild with everything in place does nothing; an extracted file whose sha256 differs from the
manifest's is an error naming it and its package. An interrupted build (Ctrl-C, kill -9) is resumed
by running it again: packages already in the manifest are kept, the rest are done afresh.
  --out DIR         the corpus folder (default corpus)
  --lists DIR       folder with photo_sources.tsv / video_sources.tsv (default: the shipped lists)
  --cache DIR       where downloaded .deb files are kept (default DIR/.debs)
  --debs DIR        take PKG_VERSION_*.deb from DIR instead of downloading (offline, tests)
  --packages LIST   only these packages (comma-separated)
  --jobs N          packages processed at once (default: all cores)
  --verify          unpack packages already in place too and check their files' sha256

list: every image under DIR, recursively, as TSV on stdout (status, file, width, height, reason);
unreadable files are listed with the reason and counted, not fatal. A summary goes to stderr.

candidates: the detector's stages up to the quad search (default detector settings) on every image
of DIR (DIR/manifest.tsv, or every image under DIR when there is no manifest, but for the stores
named corpus_candidates* in DIR itself), and for every candidate quad the 4x4, 5x5 and 6x6 payload
read with the detector's varying threshold. No pre-filter: every quad whose payload can be read is
kept (the paper's false-positive count). A folder without images is an error (nothing is written).
Files that do not decode are rows with status unreadable and the reason.
  --out FILE        the store (default DIR/corpus_candidates.bin); the image index goes beside it
                    with extension .tsv (id, file, group, kind, width, height, quads, status, reason)
  --jobs N          images processed at once (default: all cores); the store does not depend on it
  --shard i/N       only shard i (0 <= i < N) of the corpus' image list: the contiguous block of rows
                    [i*M/N, (i+1)*M/N) of its M images, for splitting a big corpus over machines. The
                    store (default DIR/corpus_candidates-shard-i-of-N.bin) records the shard, M and
                    hashes of the image list in its settings; join the N stores with `corpus merge`.
                    Every shard lists the whole corpus itself, so all must see the same folder
                    (a folder without manifest.tsv is listed by file extension and signature in
                    every shard, nothing decoded: each image is decoded once, by its shard).

merge: joins the shard stores (any order; their .tsv indexes beside them) into the store of the
whole corpus, byte for byte what `corpus candidates` without --shard writes (.bin and .tsv). It
refuses, naming the file, shards made with other detector settings, another N or another corpus
list, a shard given twice or missing, a damaged store or an index that does not fit it; nothing is
written then.
  --out FILE        the merged store (required); the index goes beside it
Example: 64 shards with GNU parallel (4 one-thread jobs at a time) or as a Slurm job array (--jobs
as allocated: the default counts every core of the node), then the merge (in any order):
  seq 0 63 | parallel -j 4 tagbench corpus candidates --corpus big --jobs 1 --shard {}/64 --out shards/{}.bin
  sbatch --array=0-63 --cpus-per-task=8 --wrap 'tagbench corpus candidates --corpus big --jobs 8 \
      --shard $SLURM_ARRAY_TASK_ID/64 --out shards/$SLURM_ARRAY_TASK_ID.bin'
  tagbench corpus merge --out big/corpus_candidates.bin shards/*.bin

score: for each family, the stored quads of its payload size whose bits decode (any rotation)
within k bits, for k = 0..K; a table (family, bits_corrected, quads, accepted, rate) on stdout.
For k > (h-1)/2 a quad is accepted when its nearest code is within k (TagFamily::decode).
A family whose payload size the store has no quad of gets rows of 0 and a note on stderr.
  --candidates FILE the store written by `corpus candidates`
  --family F        built-in name or family file; repeatable or comma-separated
  --max-bits K      the largest number of bits corrected (default 4)
  --jobs N          threads (default: all cores)
)";

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
    if (!std::filesystem::is_directory(o.lists)) throw UsageError("--lists " + *v + ": " + why_not_directory(*v));
  }
  if (auto v = a.get("cache")) o.cache = *v;
  if (auto v = a.get("debs")) {
    o.debs = *v;
    if (!std::filesystem::is_directory(o.debs)) throw UsageError("--debs " + *v + ": " + why_not_directory(*v));
  }
  if (auto v = a.get("packages")) {
    o.packages = split_commas(*v);
    if (o.packages.empty()) throw UsageError("--packages: empty list");
  }
  o.jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  o.verify = a.flag("verify");
  const auto s = corpus::build_corpus(o);
  const std::string pruned =
      s.rows_pruned ? "; " + std::to_string(s.rows_pruned) + " rows of sources no longer listed removed" : "";
  std::fprintf(stderr,
               "tagbench corpus build: %d packages built, %d already in place; %ld stills, %ld video frames "
               "written in %s%s (%.1f s)\n",
               s.packages_done, s.packages_skipped, s.stills, s.video_frames, o.out.string().c_str(), pruned.c_str(),
               s.seconds);
  return 0;
}

int corpus_list(const Words& w) {
  const Args a(w, {{"from"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto from = a.get("from");
  if (!from) throw UsageError("--from DIR is required");
  if (!std::filesystem::is_directory(*from)) throw UsageError("--from " + *from + ": " + why_not_directory(*from));
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
int corpus_candidates(const Words& w) {
  const Args a(w, {{"corpus"}, {"out"}, {"jobs"}, {"shard"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = a.get("corpus");
  if (!dir) throw UsageError("--corpus DIR is required");
  std::optional<corpus::Shard> shard;
  if (const auto v = a.get("shard")) {
    try {
      shard = corpus::parse_shard(*v);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--shard ") + e.what());
    }
  }
  if (!std::filesystem::is_directory(*dir)) throw UsageError("--corpus " + *dir + ": " + why_not_directory(*dir));
  // Each shard gets its own default name, so shards run into one folder do not overwrite each other.
  const std::string default_name =
      shard ? "corpus_candidates-shard-" + std::to_string(shard->index) + "-of-" + std::to_string(shard->count) + ".bin"
            : std::string("corpus_candidates.bin");
  const std::filesystem::path out = a.get_or("out", (std::filesystem::path(*dir) / default_name).string());
  const int jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  auto images = corpus::corpus_images(*dir);
  if (images.empty()) {
    const bool manifest = std::filesystem::exists(std::filesystem::path(*dir) / "manifest.tsv");
    throw std::runtime_error(*dir + ": no images (" +
                             (manifest ? std::string("its manifest.tsv lists none") : "no image file under it") + ")");
  }
  {  // the store (and its index beside it) must not replace an image of the corpus
    std::vector<std::filesystem::path> read;
    for (const auto& im : images) read.push_back(std::filesystem::path(*dir) / im.file);
    if (const auto hit = replaced_input(out, read))
      throw UsageError("--out " + out.string() + ": would replace " + hit->lexically_relative(*dir).string() +
                       ", an image of the corpus");
  }
  std::string shard_note;
  if (shard) {
    const auto [first, last] = corpus::shard_range(images.size(), *shard);
    shard_note = "shard " + std::to_string(shard->index) + "/" + std::to_string(shard->count) + ": rows " +
                 std::to_string(first) + " to " + std::to_string(last) + " (exclusive) of " +
                 std::to_string(images.size()) + "; ";
  }
  const auto t0 = std::chrono::steady_clock::now();
  corpus::CandidateStore store;
  {
    ProgressBar bar("candidates");
    const auto report = [&](const corpus::ExtractProgress& p) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double rate = s > 0 ? static_cast<double>(p.images_done) / s : 0;
      const double left = rate > 0 ? static_cast<double>(p.images_total - p.images_done) / rate : -1;
      char detail[96];
      std::snprintf(detail, sizeof detail, "%llu quads, %.3g images/s", static_cast<unsigned long long>(p.quads), rate);
      bar.update(p.images_total ? static_cast<double>(p.images_done) / static_cast<double>(p.images_total) : 1.0,
                 std::to_string(p.images_done) + "/" + std::to_string(p.images_total), detail, left);
    };
    store = shard ? corpus::extract_candidate_shard(*dir, images, *shard, DetectorOptions::paper(), jobs, report)
                  : corpus::extract_candidates(*dir, std::move(images), DetectorOptions::paper(), jobs, report);
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
  // A run killed while writing left its temporaries; this one's store replaces that run's.
  remove_stale_temporaries(out.has_parent_path() ? out.parent_path() : std::filesystem::path("."));
  corpus::write_candidates(out, store);
  std::size_t unreadable = 0;
  double mpix = 0;
  for (const auto& i : store.images) {
    unreadable += i.status != "ok";
    mpix += static_cast<double>(i.width) * i.height / 1e6;
  }
  std::fprintf(stderr,
               "tagbench corpus candidates: %s%zu images (%zu unreadable), %llu quads, %zu payload records in %s "
               "(%.1f s; %.3g images/s, %.3g Mpx/s, %.3g quads/s)\n",
               shard_note.c_str(), store.images.size(), unreadable, static_cast<unsigned long long>(store.quads),
               store.records.size(), out.string().c_str(), secs,
               secs > 0 ? static_cast<double>(store.images.size()) / secs : 0, secs > 0 ? mpix / secs : 0,
               secs > 0 ? static_cast<double>(store.quads) / secs : 0);
  for (const auto& i : store.images)
    if (i.status != "ok") std::fprintf(stderr, "  unreadable: %s: %s\n", i.file.c_str(), i.reason.c_str());
  return 0;
}

int corpus_merge(const Words& w) {
  const Args a(w, {{"out"}});
  const auto out = a.get("out");
  if (!out) throw UsageError("--out FILE is required");
  if (a.positionals().empty()) throw UsageError("no shard stores given (SHARD.bin...)");
  {  // the merged store (and its index beside it) must not replace a shard or its index
    std::vector<std::filesystem::path> read;
    for (const auto& f : a.positionals())
      for (const std::filesystem::path& p : {std::filesystem::path(f), std::filesystem::path(f).replace_extension(".tsv")})
        read.push_back(p);
    if (const auto hit = replaced_input(*out, read))
      throw UsageError("--out " + *out + ": would replace " + hit->string() + ", an input of the merge");
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<corpus::CandidateStore> shards;
  for (const auto& f : a.positionals()) shards.push_back(corpus::read_candidates(f, true));
  const std::size_t n = shards.size();
  // Everything is checked before anything is written, so a refused merge leaves no file behind.
  const auto store = corpus::merge_candidates(std::move(shards), a.positionals());
  const std::filesystem::path path(*out);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  remove_stale_temporaries(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
  corpus::write_candidates(path, store);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr,
               "tagbench corpus merge: %zu shards, %zu images, %llu quads, %zu payload records in %s (%.1f s)\n", n,
               store.images.size(), static_cast<unsigned long long>(store.quads), store.records.size(),
               path.string().c_str(), secs);
  return 0;
}

int corpus_score(const Words& w) {
  const Args a(w, {{"candidates"}, {"family", true, true}, {"max-bits"}, {"jobs"}});
  std::vector<std::string> names;
  for (const auto& f : a.all("family"))
    for (const auto& n : option_list("--family", f)) names.push_back(n);
  for (const auto& p : a.positionals()) names.push_back(p);
  const auto file = a.get("candidates");
  if (!file) throw UsageError("--candidates FILE is required");
  if (names.empty()) throw UsageError("--family F is required");
  const int jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  const int max_k = static_cast<int>(a.get_int("max-bits", 4, 0, 64));
  std::vector<TagFamily> families;
  for (const auto& n : names) families.push_back(usage_on_invalid("--family: ", [&] { return load_family(n); }));
  const auto store = corpus::read_candidates(*file, false);
  const auto t0 = std::chrono::steady_clock::now();
  std::printf("family\tbits_corrected\tquads\taccepted\trate\n");
  bool nearest = false;
  std::vector<std::string> without_quads;  // families the store has no quad of their payload size for
  for (const auto& f : families) {
    const int k = std::min(max_k, f.bits());
    const auto s = corpus::score_family(store.records, f, k, jobs);
    if (s.quads == 0)
      without_quads.push_back(f.name() + " (" + std::to_string(f.payload_width()) + "x" +
                              std::to_string(f.payload_width()) + ")");
    for (int i = 0; i <= k; ++i) {
      const auto acc = s.accepted[static_cast<std::size_t>(i)];
      std::printf("%s\t%d\t%llu\t%llu\t%.6g\n", f.name().c_str(), i, static_cast<unsigned long long>(s.quads),
                  static_cast<unsigned long long>(acc),
                  s.quads ? static_cast<double>(acc) / static_cast<double>(s.quads) : 0.0);
    }
    nearest = nearest || 2 * k >= f.min_hamming();
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "tagbench corpus score: %zu records, %zu families in %.2f s%s\n", store.records.size(),
               families.size(), secs,
               nearest ? "; rows with bits corrected > (h-1)/2 accept a quad whose nearest code is that close" : "");
  // Rows of 0 quads are a valid answer, but one that should not pass for "nothing was accepted".
  for (const auto& f : without_quads)
    std::fprintf(stderr, "tagbench corpus score: note: %s has no quad of the payload size of %s; its rows are 0\n",
                 file->c_str(), f.c_str());
  return 0;
}
}  // namespace

int cmd_corpus(const Words& w) {
  if (w.empty() || w[0] == "--help" || w[0] == "-h") {
    std::fputs(kCorpusHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  if (wants_help(w, kCorpusHelp)) return 0;
  constexpr Subcommand kSubcommands[] = {{"build", corpus_build},           {"list", corpus_list},
                                         {"candidates", corpus_candidates}, {"merge", corpus_merge},
                                         {"score", corpus_score}};
  return dispatch_subcommand("corpus", w, kSubcommands);
}

}  // namespace tagbench::cli
