// tagbench falsepos: the false-positive experiments on the natural-image corpus (issue 5; the
// paper's section VI-A, Figs. 6 and 7) and whole detectors' false detections on it.
#include <opencv2/core.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include "candidates.hpp"
#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "codes/families.hpp"
#include "fp_codes.hpp"
#include "fp_detectors.hpp"
#include "util/atomic_file.hpp"
#include "util/progress.hpp"
#include "util/sysinfo.hpp"

namespace tagbench::cli {

namespace {
constexpr const char* kHelp = R"(usage: tagbench falsepos complexity --candidates FILE [--out DIR] [--max-bits K] [--complexity LO-HI]
       tagbench falsepos codes --candidates FILE [--out DIR] [--max-bits K] [--family F...]
       tagbench falsepos detectors --corpus DIR [--out DIR] [--detectors LIST] [--families LIST]

The corpus holds no tags, so everything accepted is a false positive. FILE is the candidate store
written by `tagbench corpus candidates` (every candidate quad's 4x4, 5x5 and 6x6 payload bits).

complexity: the paper's Fig. 6. Ten 25h9 families generated here with minimum rectangle complexity
1..10 (seed 250900 + c, as the original generator), each scored for 0..K bits corrected (default 4),
beside the rate of random payloads, 4 N V(25, k) / 2^25. Writes DIR/fig6_complexity.csv and .json.
  --complexity LO-HI  the complexity thresholds (default 1-10)
  --bits N, --hamming H  another family shape than 25h9

codes: the paper's Fig. 7. ARToolKit+ simple, ARToolKit+ BCH, ARTag (2046), 36h10, 36h15 and 36h11
(or --family F...), 0..K bits corrected (default 7). Writes DIR/fig7_codes.csv and .json.

Rows of both: scheme, family, bits, min_hamming, min_complexity, codes, subset (all | still |
video-frame), bits_corrected, quads, accepted, rate, ci95_lo, ci95_hi (Wilson), theory_rate,
theory_exact (1 while 2k < h, where the random-payload rate is exact; an upper bound after),
generation_seconds. A quad is accepted at k when the nearest code (any rotation) is within k bits.

detectors: whole detectors at their defaults on every image of the corpus (DIR/manifest.tsv, or
every image under DIR), one family at a time: tagbench-full (ours: 1 bit corrected),
libapriltag-d2 (libapriltag 3.3's defaults: quad_decimate 2, 2 bits corrected), aruco-default
(OpenCV 4.6 aruco's defaults). Writes DIR/fp_detectors.csv (per detector, family and subset: all,
still, video-frame, group:NAME; false detections per image and per megapixel with exact Poisson 95 %
intervals, the share of images with one with its Wilson interval, ms per image and Mpx/s),
DIR/fp_detections.csv (every false detection with its image and corners) and DIR/fp_detectors.json.
  --detectors LIST  comma-separated (default tagbench-full,libapriltag-d2,aruco-default; also
                    tagbench-half, libapriltag-d1, aruco)
  --families LIST   comma-separated (default 16h5,25h9,36h11)

Common:
  --out DIR         where the results go (default results; must exist)
  --jobs N          threads (default: all cores); results do not depend on it
)";

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (const unsigned char c : s) {
    if (c == '"' || c == '\\') {
      o += '\\';
      o += static_cast<char>(c);
    } else if (c == '\n') {
      o += "\\n";
    } else if (c == '\t') {
      o += "\\t";
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
    } else {
      o += static_cast<char>(c);
    }
  }
  return o + "\"";
}

std::filesystem::path out_dir(const Args& a) {
  const std::filesystem::path dir = a.get_or("out", "results");
  if (!std::filesystem::is_directory(dir)) throw UsageError("--out " + dir.string() + ": no such directory");
  return dir;
}

corpus::CandidateStore load_store(const Args& a, std::string& file) {
  const auto f = a.get("candidates");
  if (!f) throw UsageError("--candidates FILE is required");
  file = *f;
  if (!std::filesystem::exists(file)) throw std::runtime_error(file + ": no such file");
  auto store = corpus::read_candidates(file, true);
  if (store.records.empty()) throw std::runtime_error(file + ": the store holds no payload records (no quads)");
  return store;
}

// The settings behind a family-scoring run, as the sidecar JSON.
std::string scoring_json(const std::string& command, const std::string& file, const corpus::CandidateStore& store,
                         const std::vector<ScoredFamily>& families, int max_k) {
  std::size_t readable = 0;
  for (const auto& i : store.images) readable += i.status == "ok";
  std::ostringstream js;
  js << "{\n  \"command\": " << json_string(command) << ",\n  \"candidates\": " << json_string(file)
     << ",\n  \"images\": " << store.images.size() << ",\n  \"images_readable\": " << readable
     << ",\n  \"candidate_quads\": " << store.quads << ",\n  \"payload_records\": " << store.records.size()
     << ",\n  \"detector_settings\": " << json_string(store.settings) << ",\n  \"max_bits_corrected\": " << max_k
     << ",\n  \"acceptance\": \"a quad counts at k when its payload's nearest code over all ids and rotations is "
        "within k bits (TagFamily::decode)\",\n  \"families\": [\n";
  for (std::size_t i = 0; i < families.size(); ++i) {
    const auto& f = families[i].family;
    js << "    {\"scheme\": " << json_string(families[i].scheme) << ", \"family\": " << json_string(f.name())
       << ", \"codes\": " << f.size() << ", \"min_hamming\": " << f.min_hamming()
       << ", \"min_complexity\": " << f.info().min_complexity << ", \"generator\": " << json_string(f.info().generator);
    if (f.info().seed) js << ", \"seed\": " << *f.info().seed;
    if (!f.info().order.empty()) js << ", \"order\": " << json_string(f.info().order);
    if (families[i].generation_seconds > 0) js << ", \"generation_seconds\": " << families[i].generation_seconds;
    js << "}" << (i + 1 < families.size() ? "," : "") << "\n";
  }
  js << "  ]\n}\n";
  return js.str();
}

void write_scoring(const std::filesystem::path& dir, const std::string& stem, const std::vector<CodeCurveRow>& rows,
                   const std::string& json) {
  write_files_atomic({{dir / (stem + ".csv"), code_curves_csv(rows)}, {dir / (stem + ".json"), json}});
  std::fprintf(stderr, "tagbench falsepos: wrote %s.csv and %s.json in %s\n", stem.c_str(), stem.c_str(),
               dir.string().c_str());
}

int falsepos_complexity(const Words& w) {
  const Args a(w, {{"candidates"}, {"out"}, {"max-bits"}, {"complexity"}, {"bits"}, {"hamming"}, {"jobs"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = out_dir(a);
  const int jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  const int max_k = static_cast<int>(a.get_int("max-bits", 4, 0, 64));
  const int bits = static_cast<int>(a.get_int("bits", 25, 9, 64));
  const int ham = static_cast<int>(a.get_int("hamming", 9, 1, 64));
  int lo = 1, hi = 10;
  if (auto v = a.get("complexity")) {
    const auto dash = v->find('-');
    if (dash == std::string::npos) {
      lo = hi = static_cast<int>(parse_int("--complexity", *v, 0, 64));
    } else {
      lo = static_cast<int>(parse_int("--complexity", v->substr(0, dash), 0, 64));
      hi = static_cast<int>(parse_int("--complexity", v->substr(dash + 1), 0, 64));
    }
    if (hi < lo) throw UsageError("--complexity " + *v + ": empty range");
  }
  std::string file;
  const auto store = load_store(a, file);
  std::vector<ScoredFamily> families;
  try {
    families = complexity_families(bits, ham, lo, hi, jobs);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const auto rows = code_curves(store, families, max_k, jobs);
  write_scoring(dir, "fig6_complexity", rows, scoring_json("tagbench falsepos complexity", file, store, families, max_k));
  return 0;
}

int falsepos_codes(const Words& w) {
  const Args a(w, {{"candidates"}, {"out"}, {"max-bits"}, {"family", true, true}, {"jobs"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = out_dir(a);
  const int jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  const int max_k = static_cast<int>(a.get_int("max-bits", 7, 0, 64));
  std::vector<ScoredFamily> families;
  for (const auto& f : a.all("family"))
    for (const auto& n : split_commas(f)) families.push_back({n, load_family(n), 0});
  if (families.empty()) families = fig7_schemes();
  std::string file;
  const auto store = load_store(a, file);
  const auto rows = code_curves(store, families, max_k, jobs);
  write_scoring(dir, "fig7_codes", rows, scoring_json("tagbench falsepos codes", file, store, families, max_k));
  return 0;
}

int falsepos_detectors(const Words& w) {
  const Args a(w, {{"corpus"}, {"out"}, {"detectors"}, {"families"}, {"jobs"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const auto dir = out_dir(a);
  const auto corpus_dir = a.get("corpus");
  if (!corpus_dir) throw UsageError("--corpus DIR is required");
  if (!std::filesystem::is_directory(*corpus_dir)) throw UsageError("--corpus " + *corpus_dir + ": no such directory");
  FpDetectorsOptions o;
  o.jobs = static_cast<int>(a.get_int("jobs", hardware_threads(), 1, 256));
  if (auto v = a.get("detectors")) o.detectors = split_commas(*v);
  if (auto v = a.get("families")) o.families = split_commas(*v);
  if (o.detectors.empty()) throw UsageError("--detectors: empty list");
  if (o.families.empty()) throw UsageError("--families: empty list");
  for (const auto& d : o.detectors)
    for (const auto& f : o.families) try {
        ComparatorSetup s;
        s.family = f;
        make_comparator(d, s);
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--detectors/--families: ") + e.what());
      }
  auto images = corpus::corpus_images(*corpus_dir);
  if (images.empty()) throw std::runtime_error(*corpus_dir + ": no images");
  // Images run in parallel here; OpenCV's own thread pool (aruco) would only oversubscribe the cores.
  cv::setNumThreads(1);
  const auto t0 = std::chrono::steady_clock::now();
  FpDetectorsRun run;
  {
    ProgressBar bar("false positives");
    run = run_fp_detectors(*corpus_dir, std::move(images), o, [&](const FpDetectorsProgress& p) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double rate = s > 0 ? static_cast<double>(p.images_done) / s : 0;
      const double left = rate > 0 ? static_cast<double>(p.images_total - p.images_done) / rate : -1;
      bar.update(p.images_total ? static_cast<double>(p.images_done) / static_cast<double>(p.images_total) : 1.0,
                 std::to_string(p.images_done) + "/" + std::to_string(p.images_total),
                 std::to_string(p.detections) + " detections", left);
    });
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto rows = fp_detector_rows(run);
  std::size_t unreadable = 0;
  for (const auto& i : run.images) unreadable += i.status != "ok";
  std::ostringstream js;
  js << "{\n  \"command\": \"tagbench falsepos detectors\",\n  \"corpus\": " << json_string(*corpus_dir)
     << ",\n  \"images\": " << run.images.size() << ",\n  \"images_unreadable\": " << unreadable
     << ",\n  \"detectors\": {\n"
        "    \"tagbench-full\": \"tagbench DetectorOptions defaults (sigma 0.8, 1 bit corrected, full resolution)\",\n"
        "    \"tagbench-half\": \"tagbench DetectorOptions defaults, segmentation at half resolution\",\n"
        "    \"libapriltag-d1\": \"libapriltag 3.3: quad_decimate 1, its other defaults, 2 bits corrected\",\n"
        "    \"libapriltag-d2\": \"libapriltag 3.3 defaults: quad_decimate 2, refine_edges 1, decode_sharpening 0.25, "
        "2 bits corrected\",\n"
        "    \"aruco\": \"OpenCV 4.6 aruco DICT_APRILTAG_*, CORNER_REFINE_APRILTAG\",\n"
        "    \"aruco-default\": \"OpenCV 4.6 aruco DICT_APRILTAG_*, DetectorParameters defaults\"\n  },\n"
     << "  \"run\": [";
  for (std::size_t i = 0; i < o.detectors.size(); ++i) js << (i ? ", " : "") << json_string(o.detectors[i]);
  js << "],\n  \"families\": [";
  for (std::size_t i = 0; i < o.families.size(); ++i) js << (i ? ", " : "") << json_string(o.families[i]);
  js << "],\n  \"jobs\": " << o.jobs << ",\n  \"wall_seconds\": " << secs
     << ",\n  \"cpu\": " << json_string(cpu_model_name()) << "\n}\n";
  write_files_atomic({{dir / "fp_detectors.csv", fp_detectors_csv(rows)},
                      {dir / "fp_detections.csv", fp_detections_csv(run)},
                      {dir / "fp_detectors.json", js.str()}});
  std::fprintf(stderr,
               "tagbench falsepos detectors: %zu images (%zu unreadable), %zu false detections in %.1f s; wrote "
               "fp_detectors.csv, fp_detections.csv, fp_detectors.json in %s\n",
               run.images.size(), unreadable, run.detections.size(), secs, dir.string().c_str());
  return 0;
}

}  // namespace

int cmd_falsepos(const Words& w) {
  if (w.empty() || w[0] == "--help" || w[0] == "-h") {
    std::fputs(kHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  if (wants_help(w, kHelp)) return 0;
  constexpr Subcommand kSubcommands[] = {
      {"complexity", falsepos_complexity}, {"codes", falsepos_codes}, {"detectors", falsepos_detectors}};
  return dispatch_subcommand("falsepos", w, kSubcommands);
}

}  // namespace tagbench::cli
