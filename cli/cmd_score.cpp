// tagbench score: any detector's detections (JSON lines) scored on an exported dataset, into the same
// rows, summaries and sidecar as the ray-traced sweeps (bench/score/score.hpp).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/sweep_args.hpp"
#include "score/score.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;

namespace {

constexpr const char* kScoreHelp = R"(usage: tagbench score DATASET DETECTIONS [--out DIR] [--name NAME] [--corner-order ORDER]
           [--pixel-offset P] [--tag-frame AXES]

Scores a detector's output on a dataset written by `tagbench dataset export` exactly as the ray-traced
sweeps score the built-in detectors, and writes the same files.

DATASET      the dataset folder (or its truth.json)
DETECTIONS   a file of JSON lines ('-': standard input), one line per frame of the dataset, any order:
               {"image": "frame_00000.png", "ms": 1.2,
                "detections": [{"family": "36h11", "id": 7, "corners": [[x, y], [x, y], [x, y], [x, y]],
                                "pose": {"R": [[...], [...], [...]], "t": [x, y, z]}}]}
             "ms", "pose", "decision_margin" and "hamming" are optional; "image" is the frame's file name
             or a path to it; a frame with nothing found has "detections": []. `tagbench detect
             --format jsonl` writes this format.

Options:
  --out DIR            where the results go (default score; created if missing)
  --name NAME          the detector's name in the rows (default: DETECTIONS' file name without extension)
  --corner-order ORDER the detector's corner order as our names, e.g. bl-br-tr-tl (default tl-tr-br-bl:
                       the printed tag's top-left, top-right, bottom-right, bottom-left)
  --pixel-offset P     the detector's coordinate of a pixel centre (default 0: centres at integers;
                       0.5 when pixel i covers [i, i+1)); P is subtracted from its corners
  --tag-frame AXES     the detector's tag x, y, z axes in ours, e.g. -x,y,-z (default x,y,z: x toward the
                       printed right edge, y toward the bottom edge, z into the tag; origin at the centre)

Writes into DIR, as `tagbench raytrace` (same columns): fig9_angle.csv / fig10_distance.csv /
conditions.csv / sixdof.csv (one row per frame; a dataset of another family than 36h11 adds it to the
name, e.g. fig10_distance_16h5.csv), *_summary.csv (per step, or sixdof's variable and bin:
detection rate with its Wilson 95 % interval, error percentiles) and *.json (what was scored, the
convention, the settings). Plots: /usr/bin/python3 scripts/plot_raytrace.py DIR (sixdof:
scripts/plot_sixdof.py DIR).
When the corners or poses fit the truth far better under another declaration (a reversed or rotated
corner order, a half-pixel shift, another tag frame), one line on stderr names the options.
Errors (exit 1, nothing written): a line that is not JSON or lacks a field, an image that is not a frame
of the dataset or is given twice, a frame without a line, a line with "error".
)";

}  // namespace

int cmd_score(const Words& w) {
  if (wants_help(w, kScoreHelp)) return 0;
  const Args a(w, {{"out"}, {"name"}, {"corner-order"}, {"pixel-offset"}, {"tag-frame"}});
  if (a.positionals().size() != 2) throw UsageError("expected DATASET and DETECTIONS (see tagbench score --help)");
  const std::filesystem::path dataset_path = a.positionals()[0];
  const std::string detections = a.positionals()[1];
  Convention c;
  try {
    if (a.has("corner-order")) c.order = parse_corner_order(*a.get("corner-order"));
    if (a.has("tag-frame")) c.tag_axes = parse_tag_frame(*a.get("tag-frame"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (a.has("pixel-offset")) c.pixel_offset = parse_double("--pixel-offset", *a.get("pixel-offset"), -1e6, 1e6);
  std::string name;
  if (const auto given = a.get("name")) {
    name = *given;
    if (name.empty() || name.find_first_of(",\"\r\n") != std::string::npos)
      throw UsageError("--name '" + name + "': a detector name must be non-empty, without commas, quotes or line breaks");
  } else {  // from the file name, made fit for a CSV cell: what a name may not hold becomes '_'
    name = detections == "-" ? "stdin" : std::filesystem::path(detections).stem().string();
    for (char& ch : name)
      if (ch == ',' || ch == '"' || static_cast<unsigned char>(ch) < 0x20) ch = '_';
    if (name.empty()) name = "detections";
  }
  const std::string out_text = a.get_or("out", "score");
  check_out_folder("--out", out_text);

  const Dataset dataset = read_dataset(dataset_path);
  const std::filesystem::path dir =
      std::filesystem::is_directory(dataset_path) ? dataset_path : dataset_path.parent_path();
  std::string text;
  if (detections == "-") text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  else text = read_file(detections);
  const auto lines = parse_detection_lines(text, detections);
  const ScoreResult r = score_detections(dataset, dir.empty() ? "." : dir, lines, detections, name, c);

  const std::filesystem::path out = out_text;
  const std::string stem = result_stem(r.sweep.settings);
  const bool made = std::filesystem::create_directories(out);
  remove_stale_temporaries(out);
  try {
    write_files_atomic({{out / (stem + ".csv"), rows_csv(r.sweep)},
                        {out / (stem + "_summary.csv"), summary_csv(r.sweep, summarize(r.sweep))},
                        {out / (stem + ".json"), score_sidecar_json(r, dataset_path, detections, c)}});
  } catch (...) {
    std::error_code ec;
    if (made) std::filesystem::remove(out, ec);
    throw;
  }
  std::size_t detected = 0;
  for (const auto& row : r.sweep.rows) detected += row.detected_right_id;
  if (!r.hint.empty()) std::fprintf(stderr, "tagbench score: %s\n", r.hint.c_str());
  std::fprintf(stderr, "tagbench score: %s detected %zu of %zu frames with the right id; wrote %s.csv, %s_summary.csv, %s.json in %s\n",
               name.c_str(), detected, r.sweep.rows.size(), stem.c_str(), stem.c_str(), stem.c_str(), out.string().c_str());
  return 0;
}

}  // namespace tagbench::cli
