// tagbench realistic: the detectors on the realistic image set (bench/realistic/): small tags on
// cluttered ground through a camera model, scored per tag-size bin.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/sweep_args.hpp"
#include "codes/families.hpp"
#include "realistic/realistic_ceiling.hpp"
#include "realistic/realistic_run.hpp"
#include "tools/atomic_file.hpp"
#include "tools/progress.hpp"

#include <opencv2/imgcodecs.hpp>

namespace tagbench::cli {

namespace {

constexpr const char* kRealisticHelp = R"(usage: tagbench realistic [--frames N] [--seed S] [--family F] [--detectors LIST] [--out DIR]
           [--export-frames DIR] [--ceiling] [--ideal] [--camera-gamma G] [--defocus gaussian|disk]
           [--sizes|--blur|--motion-blur|--jpeg-quality|--full-well|--ink|--face-light|--sharpen LO,HI]

The realistic image set (issue 17): frames made to behave like JPEG photographs of small tags, and
every selected detector on every frame, one thread, scored per tag against the frame's ground truth.

Frames: 800 x 600 gray, pinhole f = 800 px (principal point at the centre); 4 to 10 tags of one family,
distinct ids, black squares 12 to 40 px across (sqrt of the projected area, uniform), tilted 0 to 65
degrees about a random axis, random roll, on a card or cube face of random grey, not overlapping,
wholly in view; on a procedural cluttered ground (paving grids, rectangles, outlines, lines, blobs,
text, tag-like decoys, texture at three scales); rendered projectively at 4 x 4 samples a pixel and
box-averaged; uneven light (a smooth fall-off and often a hard shadow; tags in sun or shade, worn
or grey prints: low contrast); then a camera: Gaussian defocus, motion blur, shot and read noise, gamma (2.2), 8 bits, JPEG
at quality 70..90. Each frame is determined by (seed, frame number): the same bytes on every run.

Options:
  --frames N          frames 0..N-1 of the set (default 50; make bench uses 200)
  --seed S            the set's seed (default 1)
  --family F          the tags' family (default 36h11; libapriltag and aruco also know 16h5, 25h9, 36h10)
  --detectors LIST    comma-separated (default the eight: tagbench, tagbench-thorough, tagbench-half,
                      tagbench-paper, tagbench-paper-half, libapriltag-d1, libapriltag-d2, aruco; also
                      aruco-default)
  --out DIR           where the results go (default results; created if missing)
  --export-frames DIR also write every frame into DIR: frame-NNNNN.jpg (the JPEG the detectors decode;
                      .png with --ideal) and frame-NNNNN.json (truth: corners TL,TR,BR,BL of the black
                      square, pixel centres at integers, size, tilt, pose, tag size; the camera and
                      what it did), and set.json (the settings, written last: a folder without it
                      holds an interrupted export). DIR must be missing, empty or an earlier export
                      (only frame-NNNNN.* files and set.json): that export's files are removed first
  --ceiling           also read every tag through its TRUE corners with the default profile's decoding
                      (area and point reader; the area reader again with the soft decoder, soft_decode.hpp,
                      where it decoded nothing hard): what the payload reader could decode if the quads were
                      perfect, per size bin and contrast band (grey levels, white ring - black ring)
  --ideal             no defocus, motion blur, noise, gamma or JPEG (the geometry alone)
Ranges (LO,HI; a value per frame or tag is drawn uniformly in it; defaults are the calibrated set):
  --sizes LO,HI       black square px, sqrt of the area (default 12,40)
  --blur LO,HI        defocus sigma, px (default 0.3,1.4)
  --motion-blur LO,HI motion blur length, px (default 0,1.5)
  --jpeg-quality LO,HI  (default 70,90)
  --full-well LO,HI   electrons at white, shot noise (default 800,4000)
  --ink LO,HI         reflectance of the tag's black (default 0.04,0.5)
  --face-light LO,HI  light on the tag's face, 1 = the brightest ground (default 0.25,1)
  --sharpen LO,HI     the camera's unsharp-mask amount (sigma 1 px) before JPEG (default 0,0)
  --camera-gamma G    the camera's encoding gamma, in [1, 4] (default 2.2, as photographs; 1: a linear
                      machine-vision camera); our detectors are told it (DetectorOptions::input_gamma)
  --defocus SHAPE     the defocus PSF: gaussian (default; sigma from --blur) or disk, a lens's uniform
                      disk of radius 2 sigma (the same second moment; its edges spread evenly and
                      farther); recorded in realistic.json and the frames' JSON only when disk

Writes into DIR:
  realistic.csv          a row per tag and detector: the frame's camera values, the tag (id, black
                         square px, size bin, tilt, roll, centre, reflectances, light), detected,
                         wrong_id, corner_rms_px, decision_margin, ms (the detector on the whole frame)
  realistic_false.csv    every detection that matches no tag (id, size, centre, the tag it lies on)
  realistic_summary.csv  per size bin (12-16, 16-20, 20-24, 24-28, 28-32, 32-40 px, and all) and
                         detector: tags, detected, rate with its Wilson 95 % interval, wrong ids,
                         false detections, median and 90th percentile corner RMS
  realistic.json         the settings, how frames are made, the measures, the summary
  realistic_ceiling.csv, realistic_ceiling_summary.csv   (--ceiling) a row per tag: its contrast, whether
                         the area / area+soft / point reader decodes it from the truth corners (and bits wrong), each
                         detector's result; per size bin and contrast band: tags, ceiling, detected
Plot: /usr/bin/python3 scripts/plot_realistic.py DIR.
)";

std::string frame_name(int index, const char* ext) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "frame-%05d.%s", index, ext);
  return buf;
}

// --export-frames DIR: missing, empty or an earlier export, whose files are removed so that the
// folder never mixes frames of two sets. Anything else in it refuses the run (nothing is removed).
bool is_export_file(const std::string& name) {
  // set.json, frame-N.jpg|png|json (N five digits or more: frame_name), or a temporary of one
  // (TARGET.tmp.OWNER; remove_stale_temporaries).
  const auto mine = [](std::string_view n) {
    if (n == "set.json") return true;
    if (!n.starts_with("frame-")) return false;
    const std::size_t dot = n.find('.', 6);
    if (dot == std::string_view::npos || dot < 11) return false;
    for (std::size_t i = 6; i < dot; ++i)
      if (n[i] < '0' || n[i] > '9') return false;
    const std::string_view ext = n.substr(dot);
    return ext == ".jpg" || ext == ".png" || ext == ".json";
  };
  const auto tmp = name.find(".tmp.");
  return mine(tmp == std::string::npos ? std::string_view(name) : std::string_view(name).substr(0, tmp));
}

void prepare_export_folder(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    fs::create_directories(dir);
    return;
  }
  std::vector<fs::path> old;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (!is_export_file(name) || !e.is_regular_file(ec))
      throw UsageError("--export-frames " + dir.string() + ": not empty and not an earlier export ('" + name +
                       "' is not one of its files): choose another folder");
    if (name.find(".tmp.") == std::string::npos) old.push_back(e.path());
  }
  remove_stale_temporaries(dir);
  for (const auto& p : old) fs::remove(p);  // throws naming the path when it cannot
}

}  // namespace

int cmd_realistic(const Words& w) {
  if (wants_help(w, kRealisticHelp)) return 0;
  const Args a(w, {{"frames"}, {"seed"}, {"family"}, {"detectors"}, {"out"}, {"export-frames"}, {"ceiling", false}, {"ideal", false},
                   {"sizes"}, {"blur"}, {"motion-blur"}, {"jpeg-quality"}, {"full-well"}, {"ink"}, {"face-light"}, {"sharpen"}, {"camera-gamma"},
                   {"defocus"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  bench::RealisticRunSettings s;
  s.frames = static_cast<int>(a.get_int("frames", 50, 1, 1000000));
  if (a.has("seed")) s.set.seed = static_cast<std::uint64_t>(parse_int("--seed", *a.get("seed"), 0, (1LL << 62)));
  if (a.has("family")) s.set.family = *a.get("family");
  if (a.has("detectors")) s.detectors = split_items("--detectors", *a.get("detectors"));
  s.set.degrade = !a.flag("ideal");
  const auto range = [&](const char* name, bench::Range& r) {
    if (!a.has(name)) return;
    const std::string opt = std::string("--") + name;
    const auto items = split_items(opt, *a.get(name));
    if (items.size() != 2) throw UsageError(opt + ": want LO,HI (got '" + *a.get(name) + "')");
    r = {parse_double(opt, items[0], -1e300, 1e300), parse_double(opt, items[1], -1e300, 1e300)};
  };
  range("sizes", s.set.black_square_px);
  range("blur", s.set.blur_sigma_px);
  range("motion-blur", s.set.motion_blur_px);
  range("jpeg-quality", s.set.jpeg_quality);
  range("full-well", s.set.full_well_e);
  range("ink", s.set.ink_reflectance);
  range("face-light", s.set.face_light);
  range("sharpen", s.set.sharpen_amount);
  if (a.has("camera-gamma")) s.set.gamma = parse_double("--camera-gamma", *a.get("camera-gamma"), 1, 4);
  if (a.has("defocus")) {
    const std::string shape = *a.get("defocus");  // a copy: get() returns by value
    if (shape != "gaussian" && shape != "disk") throw UsageError("--defocus: want gaussian or disk (got '" + shape + "')");
    s.set.disk_defocus = shape == "disk";
  }
  try {
    s = bench::resolve_run_settings(s);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  } catch (const std::out_of_range& e) {  // an unknown family
    throw UsageError(std::string("--family: ") + e.what());
  }
  const std::filesystem::path out = a.get_or("out", "results");
  check_out_folder("--out", out.string());
  std::optional<std::filesystem::path> export_dir;
  if (a.has("export-frames")) {
    export_dir = *a.get("export-frames");
    check_out_folder("--export-frames", export_dir->string());
    prepare_export_folder(*export_dir);
  }

  std::optional<ProgressBar> bar;
  char detail[64];
  std::snprintf(detail, sizeof detail, "(%zu detectors, one thread)", s.detectors.size());
  const auto progress = [&](std::size_t done, std::size_t total) {
    if (!bar) bar.emplace("realistic");
    char count[64];
    std::snprintf(count, sizeof count, "%zu/%zu frames", done, total);
    bar->update(static_cast<double>(done) / static_cast<double>(total), count, detail, -1);
  };
  const bool ceiling = a.flag("ceiling");
  bench::CeilingResult ceiling_result;
  const DetectorOptions default_profile;
  const TagFamily family = load_family(s.set.family);
  const auto on_frame = [&](const bench::RealisticFrame& f) {
    if (ceiling) {
      const ImageF gray = to_float_image(ImageU8View{f.image.cols, f.image.rows, static_cast<int>(f.image.step), f.image.data});
      auto& readings = ceiling_result.by_frame.emplace_back();
      for (const auto& t : f.tags) readings.push_back(bench::read_at_truth(gray, t, family, default_profile));
    }
    if (!export_dir) return;
    std::string pixels;
    if (!f.jpeg.empty()) {
      pixels.assign(f.jpeg.begin(), f.jpeg.end());
    } else {
      std::vector<std::uint8_t> png;
      if (!cv::imencode(".png", f.image, png)) throw std::runtime_error("PNG encoding failed");
      pixels.assign(png.begin(), png.end());
    }
    write_files_atomic({{*export_dir / frame_name(f.index, f.jpeg.empty() ? "png" : "jpg"), pixels},
                        {*export_dir / frame_name(f.index, "json"), bench::frame_truth_json(s.set, f)}});
  };
  const bench::RealisticResult r = bench::run_realistic(s, on_frame, progress);
  bar.reset();
  const auto summary = bench::summarize_realistic(r);

  const bool made_out = std::filesystem::create_directories(out);
  remove_stale_temporaries(out);
  try {
    std::vector<std::pair<std::filesystem::path, std::string>> files = {
        {out / "realistic.csv", bench::realistic_rows_csv(r)},
        {out / "realistic_false.csv", bench::realistic_false_csv(r)},
        {out / "realistic_summary.csv", bench::realistic_summary_csv(r, summary)},
        {out / "realistic.json", bench::realistic_sidecar_json(r, summary)}};
    if (ceiling) {
      files.emplace_back(out / "realistic_ceiling.csv", bench::ceiling_rows_csv(r, ceiling_result));
      files.emplace_back(out / "realistic_ceiling_summary.csv",
                         bench::ceiling_summary_csv(r, bench::summarize_ceiling(r, ceiling_result)));
    }
    write_files_atomic(files);
    if (export_dir) write_file_atomic(*export_dir / "set.json", bench::realistic_sidecar_json(r, summary));
  } catch (...) {
    std::error_code ec;
    if (made_out) std::filesystem::remove(out, ec);  // only if still empty
    throw;
  }
  std::size_t tags = 0;
  for (const auto& f : r.frames) tags += f.tags.size();
  std::fprintf(stderr, "tagbench realistic: %zu frames, %zu tags x %zu detectors; wrote realistic.csv, "
               "realistic_false.csv, realistic_summary.csv, realistic.json in %s%s\n",
               r.frames.size(), tags, s.detectors.size(), out.string().c_str(),
               export_dir ? (std::string(" and the frames in ") + export_dir->string()).c_str() : "");
  return 0;
}

}  // namespace tagbench::cli
