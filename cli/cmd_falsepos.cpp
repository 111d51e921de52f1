// tagbench falsepos: the false-positive experiments on the natural-image corpus (issue 5; the
// paper's section VI-A, Figs. 6 and 7) and whole detectors' false detections on it. Here the help,
// the dispatch and the candidate-store experiments (complexity, codes); the whole detectors' runs
// (detectors, margin) are in falsepos_detectors.cpp.
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "candidates.hpp"
#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/falsepos_detectors.hpp"
#include "codes/families.hpp"
#include "fp_codes.hpp"
#include "tools/atomic_file.hpp"
#include "tools/json.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace falsepos_cmd {

std::filesystem::path out_dir(const Args& a) {
  const std::filesystem::path dir = a.get_or("out", "results");
  if (!std::filesystem::is_directory(dir)) throw UsageError("--out " + dir.string() + ": " + why_not_directory(dir.string()));
  return dir;
}

}  // namespace falsepos_cmd

namespace {

using namespace falsepos_cmd;  // out_dir, and the subcommands of falsepos_detectors.cpp

constexpr const char* kFalseposHelp = R"(usage: tagbench falsepos complexity --candidates FILE [--out DIR] [--max-bits K] [--complexity LO-HI]
       tagbench falsepos codes --candidates FILE [--out DIR] [--max-bits K] [--family F...]
       tagbench falsepos detectors --corpus DIR [--out DIR] [--detectors LIST] [--families LIST]
       tagbench falsepos margin --corpus DIR [--out DIR] [--families LIST] [--thresholds LIST]
                [--trials N] [--seed S] [--distances LIST] [--conditions LIST] [--cache DIR]
                [--processes P] [--povray PATH]

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
every image under DIR), one family at a time: tagbench (ours, default profile: bits corrected by family,
16h5 1, 25h9 2, 36h11 3), tagbench-thorough (the thorough profile: the default with its quads
from straight edges found at full resolution, and the coarse pass), tagbench-paper (the paper's detector: 1 bit corrected),
libapriltag-d2 (libapriltag 3.3's defaults: quad_decimate 2, 2 bits corrected), aruco-default
(OpenCV 4.6 aruco's defaults). Writes DIR/fp_detectors.csv (per detector, family and subset: all,
still, video-frame, group:NAME; false detections per image and per megapixel with exact Poisson 95 %
intervals, the share of images with one with its Wilson interval, ms per image and Mpx/s),
DIR/fp_detections.csv (every false detection with its image and corners) and DIR/fp_detectors.json.
  --detectors LIST  comma-separated (default tagbench,tagbench-thorough,tagbench-paper,libapriltag-d2,
                    aruco-default; also tagbench-half, tagbench-paper-half, libapriltag-d1, aruco;
                    external:NAME=COMMAND,
                    a detector outside the build run once on every readable image, as in tagbench
                    raytrace --help: its detections count under the family each names)
  --external-timeout S  seconds an external detector may take for all the images (default 1800)
  --families LIST   comma-separated (default 16h5,25h9,36h11)

margin: beyond the paper, what a minimum decision margin (tagbench detect --min-margin) buys and
costs. The paper's detector (tagbench-paper, margin 0) on every corpus image (false side) and on ray-traced
frames of the same family (true side: the distance sweep of `tagbench raytrace distance`, and the
conditions of the conditions sweep, default noise and blur); each threshold is scored from those
detections, which is exactly what a run at that threshold gives. Writes DIR/margin_tradeoff.csv (per
family and threshold: false detections per image with the exact Poisson interval, the share of images
with one, and per part of the true side frames, detected, rate with its Wilson interval;
distance_range_m: the largest distance up to which every step is detected in >= 90 % of its frames),
DIR/margin_tradeoff_steps.csv (the rate per family, threshold, part and step) and
DIR/margin_tradeoff.json (the settings).
  --families LIST   comma-separated (default 16h5,25h9)
  --thresholds LIST ascending, in 0..1 (default 0,0.05,...,0.95)
  --trials N        ray-traced frames per step and strength (default 10; make bench uses 50)
  --seed S          the sweeps' seed (default 1)
  --distances LIST  the distance sweep's distances, metres (default those of tagbench raytrace
                    distance from 3 m: 3..10 m, then 12.5..60 m; at 2 m a 16h5 tag does not fit)
  --conditions LIST conditions of the conditions sweep (default noise,blur; "none": no conditions sweep)
  --cache, --processes, --povray  as for tagbench raytrace

Common:
  --out DIR         where the results go (default results; must exist)
  --jobs N          threads (default: all cores); results do not depend on it
)";

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
    for (const auto& n : option_list("--family", f))
      families.push_back({n, usage_on_invalid("--family: ", [&] { return load_family(n); }), 0});
  if (families.empty()) families = fig7_schemes();
  std::string file;
  const auto store = load_store(a, file);
  const auto rows = code_curves(store, families, max_k, jobs);
  write_scoring(dir, "fig7_codes", rows, scoring_json("tagbench falsepos codes", file, store, families, max_k));
  return 0;
}

}  // namespace

int cmd_falsepos(const Words& w) {
  if (w.empty() || w[0] == "--help" || w[0] == "-h") {
    std::fputs(kFalseposHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  if (wants_help(w, kFalseposHelp)) return 0;
  constexpr Subcommand kSubcommands[] = {
      {"complexity", falsepos_complexity},
      {"codes", falsepos_codes},
      {"detectors", falsepos_detectors},
      {"margin", falsepos_margin}};
  return dispatch_subcommand("falsepos", w, kSubcommands);
}

}  // namespace tagbench::cli
