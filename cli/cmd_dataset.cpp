// tagbench dataset export: a ray-traced sweep's frames and their ground truth as files anyone can use
// without our code (bench/dataset/dataset.hpp).
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/sweep_args.hpp"
#include "cli/sweep_progress.hpp"
#include "dataset/dataset.hpp"
#include "tools/progress.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;

namespace {

constexpr const char* kDatasetHelp = R"(usage: tagbench dataset export angle|distance|conditions|sixdof --out DIR [--trials N] [--tag-size M]
           [--seed S] [--family F] [--scene plain|realistic] [--distance D] [--angles LIST] [--distances LIST]
           [--conditions LIST] [--processes P] [--cache DIR] [--povray PATH]
           sixdof: [--frames N] [--distance-range A,B] [--phi-max DEG] [--lens K1,K2,P1,P2,K3] [--defocus-max PX]
           [--noise-max LEVELS]

Writes the frames of a ray-traced sweep (the same frames `tagbench raytrace` runs its detectors on, with
the same options and defaults, its condition applied) as 8-bit gray PNG files, and one truth.json with
the camera, the conventions and every frame's ground truth, so that any detector can be run on them and
scored (`tagbench score DIR DETECTIONS`). Rendering shares the sweeps' frame cache (--cache).

  DIR/frame_NNNNN.png   NNNNN: the frame's place in the sweep's plan (step or condition and strength,
                        then trial); a frame POV-Ray fails to render is left out (listed in "failed")
  DIR/truth.json        {"format": "tagbench-dataset 1", "experiment", "settings",
                         "camera": {width, height, fx, fy, cx, cy, distortion [k1,k2,p1,p2,k3]},
                         "conventions": {pixel_centres "integer", corner_order "tl-tr-br-bl",
                                         intensity_gamma 1 (the frames are linear), ...},
                         "frames": [{file, index, condition, strength, step, step_unit, trial, seed,
                                     family, id, tag_size_m, R [[3] x3], t [3], corners [[x,y] x4],
                                     black_square_px, distortion (this frame's lens, or null),
                                     view {distance_m, phi_deg, tilt_axis_deg, roll_deg, image_x, image_y},
                                     sixdof only: camera_effects {halton_index, image_x, image_y (the
                                     centre in the distorted image), defocus_sigma_px, noise_sigma,
                                     noise_seed, quantization_bits}}],
                         "failed": [{index, error}]}
Conventions: pixel centres at integer coordinates; corners TL, TR, BR, BL of the printed black square;
camera frame x right, y down, z forward; tag frame origin at the centre, x right, y down (as printed),
z into the tag; X_camera = R X_tag + t in metres; tag size = the black square's edge.

The files are written as one result (temporaries renamed at the end). DIR must be missing, empty or an
earlier dataset (replaced; its frames that the new one lacks are removed).

Options: those of `tagbench raytrace` (see its --help) that choose the frames, and
  --out DIR           where the dataset goes (required)
)";

int export_dataset(const Words& w) {
  if (wants_help(w, kDatasetHelp)) return 0;
  std::vector<OptionSpec> specs = sweep_option_specs();
  for (const char* o : {"processes", "cache", "povray", "out"}) specs.emplace_back(o);
  const Args a(w, specs);
  if (a.positionals().empty()) throw UsageError("which experiment? angle, distance, conditions or sixdof");
  if (a.positionals().size() > 1) throw UsageError("unexpected argument '" + a.positionals()[1] + "'");
  if (!a.has("out")) throw UsageError("--out DIR is required (where the dataset goes)");
  const SweepSettings s = parse_sweep_settings(a.positionals()[0], a, {comparator_names().front()});
  const std::string out = *a.get("out");
  check_out_folder("--out", out);
  {
    std::error_code ec;
    if (std::filesystem::is_directory(out, ec) && !std::filesystem::is_empty(out, ec) &&
        !std::filesystem::exists(std::filesystem::path(out) / "truth.json", ec))
      throw UsageError("--out " + out + ": not empty and not a dataset (no truth.json)");
  }
  RenderOptions ro = render_options(a);
  std::optional<ProgressBar> bar;
  ro.progress = [&](std::size_t done, std::size_t total) {
    if (!bar) bar.emplace("dataset export: rendering");
    bar->update(total ? static_cast<double>(done) / static_cast<double>(total) : 1.0,
                std::to_string(done) + "/" + std::to_string(total) + " frames", "", -1);
  };
  const DatasetFiles files = make_dataset(s, ro);
  bar.reset();
  write_dataset(out, files);
  std::fprintf(stderr,
               "tagbench dataset export %s: %zu frames (%zu rendered, %zu from the cache, %zu failed) and truth.json "
               "in %s\n",
               experiment_name(s.experiment), files.frames.size(), files.rendered, files.from_cache, files.failed,
               out.c_str());
  return 0;
}

constexpr const char* kTopHelp = R"(usage: tagbench dataset export angle|distance|conditions|sixdof --out DIR [options]

  export   a ray-traced sweep's frames (PNG) and their ground truth (truth.json) for any detector;
           run 'tagbench dataset export --help' for the options and the format
)";

}  // namespace

int cmd_dataset(const Words& w) {
  if (w.empty() || w[0] == "--help" || w[0] == "-h") {
    std::fputs(kTopHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  constexpr Subcommand kSubcommands[] = {{"export", export_dataset}};
  return dispatch_subcommand("dataset", w, kSubcommands);
}

}  // namespace tagbench::cli
