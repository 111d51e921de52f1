// tagbench speed: detector speed on whole image sets (bench/speed/speed_sets.hpp), every detector
// single-threaded in this one process, ratios per image against a peer.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "codes/families.hpp"
#include "raytrace/comparators.hpp"
#include "speed/speed_sets.hpp"
#include "tools/atomic_file.hpp"
#include "tools/json.hpp"
#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

namespace {

constexpr const char* kSpeedHelp = R"(usage: tagbench speed [--sets LIST] [--corpus DIR] [--cache DIR] [--max-images N]
           [--realistic-frames N] [--seed S] [--scenes-per-size N] [--detectors LIST] [--pairs LIST] [--family F] [--repeats R] [--out DIR]

Detector speed on whole image sets, each reported apart: every detector single-threaded, in this one
process, on the same 8-bit gray image one after the other (the order rotated from image to image),
one warm workspace per detector, the fastest of --repeats runs kept. A pair A:B gives, per set, the
geometric mean over the images of A's time / B's time with a 95 % interval, the median ratio and the
share of images on which A was faster.

  --sets LIST            any of corpus, raytrace, realistic, scenes (default all four)
  --corpus DIR           corpus: the natural-image corpus (default corpus; tagbench corpus build)
  --cache DIR            raytrace: a ray-traced frame cache (default build/raytrace-cache, as make bench)
  --max-images N         at most N images of each set, evenly spread over it (default 0: all)
  --realistic-frames N   realistic: frames of the realistic set (default 100; tagbench realistic)
  --seed S               realistic: the set's seed (default 1)
  --scenes-per-size N    scenes: make_scene images per size, 640x480, 1280x720, 1920x1080 (default 5)
  --detectors LIST       comparator names (default tagbench,tagbench-thorough,tagbench-half,tagbench-paper,
                         tagbench-paper-half,libapriltag-d1,libapriltag-d2,aruco)
  --pairs LIST           A:B pairs (default tagbench:libapriltag-d1,tagbench-thorough:libapriltag-d1,
                         tagbench-half:libapriltag-d2,tagbench-paper:libapriltag-d1,
                         tagbench-paper-half:libapriltag-d2)
  --family F             the family every detector looks for (default 36h11)
  --repeats R            timed runs per image and detector, fastest kept (default 1)
  --out DIR              where the results go (default results)

Writes DIR/speed.csv (per set and detector: images, megapixels, total and median ms, Mpx/s, and the
pair's ratio), DIR/speed_images.csv (a row per image and detector) and DIR/speed.json (settings).
)";

std::vector<std::pair<std::string, std::string>> parse_pairs(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& item : option_list("--pairs", text, true)) {
    const auto colon = item.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())
      throw UsageError("--pairs: '" + item + "' is not A:B");
    out.emplace_back(item.substr(0, colon), item.substr(colon + 1));
  }
  return out;
}

}  // namespace

int cmd_speed(const Words& w) {
  if (wants_help(w, kSpeedHelp)) return 0;
  const Args a(w, {{"sets"}, {"corpus"}, {"cache"}, {"max-images"}, {"scenes-per-size"}, {"realistic-frames"}, {"seed"}, {"detectors"},
                   {"pairs"}, {"family"}, {"repeats"}, {"out"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  bench::SpeedOptions o;
  o.detectors = option_list("--detectors", a.get_or(
      "detectors",
      "tagbench,tagbench-thorough,tagbench-half,tagbench-paper,tagbench-paper-half,libapriltag-d1,libapriltag-d2,aruco"));
  o.family = a.get_or("family", "36h11");
  usage_on_invalid("--family: ", [&] { builtin_family(o.family); });  // the sets render built-in families
  for (const auto& d : o.detectors)  // unknown names (or a family a detector lacks) fail before any image is read
    usage_on_invalid("--detectors: ", [&] {
      bench::ComparatorSetup setup;
      setup.family = o.family;
      bench::make_comparator(d, setup);
    });
  o.repeats = static_cast<int>(a.get_int("repeats", 1, 1, 100));
  const auto pairs = parse_pairs(a.get_or("pairs",
                                          "tagbench:libapriltag-d1,tagbench-thorough:libapriltag-d1,"
                                          "tagbench-half:libapriltag-d2,tagbench-paper:libapriltag-d1,"
                                          "tagbench-paper-half:libapriltag-d2"));
  for (const auto& [x, y] : pairs)
    for (const auto& n : {x, y})
      if (std::find(o.detectors.begin(), o.detectors.end(), n) == o.detectors.end())
        throw UsageError("--pairs: '" + n + "' is not among --detectors");
  const auto sets = option_list("--sets", a.get_or("sets", "corpus,raytrace,realistic,scenes"));
  const auto max_images = static_cast<std::size_t>(a.get_int("max-images", 0, 0, 1000000000));
  const int per_size = static_cast<int>(a.get_int("scenes-per-size", 5, 1, 1000));
  const std::filesystem::path out = a.get_or("out", "results");

  // Every set is resolved (and every detector made) before anything is timed or written.
  std::vector<bench::ImageSet> image_sets;
  for (const auto& name : sets) {
    try {
      if (name == "corpus") {
        const std::filesystem::path dir = a.get_or("corpus", "corpus");
        if (!std::filesystem::is_directory(dir)) throw UsageError("--corpus " + dir.string() + ": no such folder");
        image_sets.push_back(bench::corpus_set(dir));
      } else if (name == "raytrace") {
        image_sets.push_back(bench::raytrace_cache_set(a.get_or("cache", "build/raytrace-cache")));
      } else if (name == "realistic") {
        image_sets.push_back(bench::realistic_set(static_cast<int>(a.get_int("realistic-frames", 100, 1, 1000000)),
                                                  static_cast<std::uint64_t>(a.get_int("seed", 1, 0, 1LL << 62)),
                                                  o.family));
      } else if (name == "scenes") {
        image_sets.push_back(bench::scene_set({{640, 480}, {1280, 720}, {1920, 1080}}, per_size, o.family));
      } else {
        throw UsageError("--sets: unknown set '" + name + "' (corpus, raytrace, realistic, scenes)");
      }
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--sets ") + name + ": " + e.what());
    }
    image_sets.back() = bench::spread_subset(std::move(image_sets.back()), max_images);
    if (image_sets.back().size == 0) throw UsageError("--sets " + name + ": the set has no image");
  }

  cv::setNumThreads(1);  // every detector single-threaded (aruco uses OpenCV's pool)
  std::vector<bench::SpeedRow> rows;
  for (const auto& set : image_sets) {
    ProgressBar bar("speed " + set.name, isatty(STDERR_FILENO) != 0);
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = bench::time_image_set(set, o, [&](const bench::SpeedProgress& p) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double frac = static_cast<double>(p.done) / static_cast<double>(p.total);
      bar.update(frac, std::to_string(p.done) + "/" + std::to_string(p.total), "images",
                 frac > 0 ? s / frac - s : 0);
    });
    rows.insert(rows.end(), r.begin(), r.end());
  }

  std::ostringstream settings;
  settings << "threads=1;repeats=" << o.repeats << ";family=" << o.family << ";cpu=" << cpu_model_name();
  for (const auto& set : image_sets) settings << ";" << set.name << "=" << set.source;
  const auto summary = bench::summarise_speed(rows);
  const auto ratios = bench::speed_ratios(rows, pairs);

  std::ostringstream js;
  js << "{\n  \"command\": \"tagbench speed\",\n  \"threads\": 1,\n  \"repeats\": " << o.repeats
     << ",\n  \"family\": " << json_string(o.family) << ",\n  \"cpu\": " << json_string(cpu_model_name())
     << ",\n  \"sets\": [";
  for (std::size_t i = 0; i < image_sets.size(); ++i)
    js << (i ? ", " : "") << "{\"name\": " << json_string(image_sets[i].name)
       << ", \"source\": " << json_string(image_sets[i].source) << ", \"images\": " << image_sets[i].size << "}";
  js << "],\n  \"detectors\": [";
  for (std::size_t i = 0; i < o.detectors.size(); ++i) js << (i ? ", " : "") << json_string(o.detectors[i]);
  js << "],\n  \"pairs\": [";
  for (std::size_t i = 0; i < pairs.size(); ++i)
    js << (i ? ", " : "") << "[" << json_string(pairs[i].first) << ", " << json_string(pairs[i].second) << "]";
  js << "]\n}\n";

  std::filesystem::create_directories(out);
  write_files_atomic({{out / "speed.csv", bench::speed_summary_csv(summary, ratios, settings.str())},
                      {out / "speed_images.csv", bench::speed_rows_csv(rows, settings.str())},
                      {out / "speed.json", js.str()}});
  for (const auto& q : ratios)
    std::fprintf(stderr, "tagbench speed: %s: %s / %s = %.3f (95%% %.3f-%.3f) over %zu images\n", q.set.c_str(),
                 q.detector.c_str(), q.peer.c_str(), q.geometric_mean, q.ci_lo, q.ci_hi, q.images);
  return 0;
}

}  // namespace tagbench::cli
