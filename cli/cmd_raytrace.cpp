// tagbench raytrace: the localization experiments of the paper's section VI-B (Figs. 9 and 10) and the
// conditions beyond it, on POV-Ray frames, every selected detector on every frame (bench/raytrace/sweeps.hpp).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/sweep_args.hpp"
#include "cli/sweep_progress.hpp"
#include "raytrace/sweeps.hpp"
#include "tools/atomic_file.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace {

constexpr const char* kRaytraceHelp = R"(usage: tagbench raytrace angle|distance|conditions|sixdof [--trials N] [--tag-size M] [--seed S]
           [--detectors LIST] [--family F] [--scene plain|realistic] [--distance D] [--angles LIST] [--distances LIST]
           [--conditions LIST] [--processes P] [--cache DIR] [--povray PATH] [--out DIR] [--external-timeout S]
           sixdof: [--frames N] [--distance-range A,B] [--phi-max DEG] [--lens K1,K2,P1,P2,K3] [--defocus-max PX]
           [--noise-max LEVELS] [--bins N]

The localization experiments of the paper's section VI-B on ray-traced frames: POV-Ray 3.7, a pinhole
camera of 400 x 400 pixels with f = 400 px as in the paper, a 36h11 tag (the family all five detectors
know; --family for another) with random id. Every selected detector runs on every frame, one thread, and is scored against
the frame's ground truth in our conventions.

  angle        Fig. 9. The tag at a fixed distance (--distance, default 1 m: the default 0.166 m black
               square is then 66 px wide face-on, big enough that every detector finds it face-on so that
               the fall-off comes from the angle alone, small enough that the whole tag stays in view at
               every angle and position); phi, the angle between the tag's normal and the direction to
               the camera, from 0 to 85 degrees in 5-degree steps (--angles); random tilt axis, in-plane
               rotation, id and image position (within 100 px of the centre), the same draws at every step.
  distance     Fig. 10. Face-on (phi = 0), a 1 m tag by default, 2 to 10 m in 1 m steps, then 12.5 to 60 m
               in 2.5 m steps (--distances): black squares of 200 down to 6.7 px. 1 m is left out: a 1 m
               black square at 1 m would be 400 px, the whole image. Random in-plane rotation, id and image
               position (within 20 px of the centre). Every row records the black square's width in pixels.
  conditions   Beyond the paper. A base frame per trial (--distance, default 1 m; phi uniform in 0..30
               degrees; random axis, rotation, id, position within 100 px) under each condition at four
               strengths and a zero-strength baseline, which is the plain frame itself:
                 noise       Gaussian noise added to the 8-bit image, sigma 4, 8, 16, 32 levels (seeded)
                 blur        defocus, Gaussian blur of the render, sigma 1, 2, 3, 4 px
                 gradient    light falling off linearly across the tag by 25, 50, 75, 90 %
                 occlusion   a dark patch in front of the middle 20, 40, 60, 80 % of one border edge
                 bent        the tag folded along its centre line by 10, 20, 30, 40 degrees
                 distortion  barrel lens distortion, OpenCV's k1 = -0.05, -0.1, -0.2, -0.3 (remapped);
                             ours and aruco's pose get the coefficients, libapriltag (no distortion model
                             in its estimate_tag_pose) the pinhole intrinsics only
  sixdof       Beyond the paper: the FMAC protocol's 6-DoF sweep (arXiv 2601.07723). --frames frames, each
               a scrambled Halton point (bases 2, 3, 5, 7, 11, 13, 17, 19; the scramble, a random digit
               permutation per dimension and digit position, is drawn from --seed) of all six pose
               variables: distance (uniform in --distance-range, default 0.5,6 m: the 0.166 m black
               square is 133 down to 11 px wide), phi (0..--phi-max, default 80 degrees), tilt axis and
               roll (0..360), and the tag centre's image position x, y anywhere in the image; plus the
               frame's defocus and noise. The rule for "in view": a point is skipped unless the whole
               printed tag (white border included) is 2 px inside the image both in the pinhole render
               and through the lens, so close tags sit nearer the centre. The camera is closer to a real
               one: the 400 x 400, f = 400 px render remapped through OpenCV's lens model (--lens, default
               k1,k2,p1,p2,k3 = -0.2,0.05,0.001,-0.0005,0; truth corners: cv::projectPoints with it;
               a barrel lens sees past the render's edges, where the render's border is repeated:
               unseen on the plain scene's uniform grey, visible in the realistic scene's corners),
               Gaussian defocus (sigma uniform in 0..--defocus-max, default 1.5 px), Gaussian sensor noise
               (sigma uniform in 0..--noise-max, default 4 levels, seeded) and 8-bit quantization, all
               recorded per row. Ours and aruco's pose get the lens; libapriltag (no distortion model in
               its estimate_tag_pose) the pinhole intrinsics only. The summary bins every variable
               (--bins, default 10) and the plot shows each outcome against each pose variable

Options:
  --trials N          frames per step or strength (default 5; make bench uses 50)
  --frames N          sixdof: frames (default 100; make bench uses 1000)
  --tag-size M        edge of the black square, metres (default 0.166; 1 for distance)
  --seed S            seed of every random draw (default 1); each frame's seed is in its row
  --detectors LIST    comma-separated (default all seven): tagbench, tagbench-half (ours, default profile,
                      at full and half resolution), tagbench-paper, tagbench-paper-half (the paper's
                      detector, full and half resolution), libapriltag-d1, libapriltag-d2 (AprilTag 3.3, quad_decimate 1
                      and 2), aruco (OpenCV 4.6, DICT_APRILTAG_36h11, CORNER_REFINE_APRILTAG)
                      external:NAME=COMMAND: a detector outside the build, run once on all the frames:
                      COMMAND (split as a shell would, no shell run) reads the images' paths on stdin, one a
                      line, and prints one JSON line per image in any order (the format of tagbench score
                      --help, our conventions); its rows are under NAME. A crash, a hang past
                      --external-timeout, a bad line or an image left out stops the run with one line
                      naming NAME and the image, before anything is written
  --external-timeout S  seconds an external detector may take for all the frames (default 1800)
  --family F          the tag family (default 36h11; libapriltag and aruco also know 16h5, 25h9,
                      36h10; ours any built-in family or family file)
  --scene NAME        plain (default: a self-lit tag on uniform grey) or realistic (a light, a brick wall
                      and a checkered floor)
  --distance D        angle and conditions: the fixed distance, metres (default 1)
  --angles LIST       angle: phi values, degrees in [0, 90) (default 0,5,...,85)
  --distances LIST    distance: metres, > 0 (default 2,3,...,10,12.5,15,...,60)
  --conditions LIST   conditions: a subset of noise,blur,gradient,occlusion,bent,distortion (default all)
  --distance-range A,B  sixdof: metres, 0 < A <= B (default 0.5,6)
  --phi-max DEG       sixdof: the largest phi, in [0, 90) (default 80)
  --lens K1,K2,P1,P2,K3  sixdof: OpenCV's distortion coefficients (default -0.2,0.05,0.001,-0.0005,0)
  --defocus-max PX    sixdof: the largest defocus sigma, pixels (default 1.5)
  --noise-max LEVELS  sixdof: the largest noise sigma, 8-bit levels (default 4)
  --bins N            sixdof: bins per variable in the summary (default 10)
  --processes P       povray processes at once (default: one per core)
  --cache DIR         the frame cache (default $XDG_CACHE_HOME/tagbench/raytrace, else
                      ~/.cache/tagbench/raytrace): a rerun renders nothing, an interrupted run resumes
  --povray PATH       the POV-Ray executable (default povray, from PATH)
  --out DIR           where the results go (default results; created if missing)

Writes into DIR, for angle / distance / conditions:
  fig9_angle.csv / fig10_distance.csv / conditions.csv  (with --family other than 36h11 the family is
      added to every file's name, so that it does not overwrite the 36h11 run: fig10_distance_16h5.csv,
      fig10_distance_16h5_summary.csv, fig10_distance_16h5.json; a family file by its name without
      extension)
      one row per frame and detector: experiment, condition, step, step_unit, trial, seed, id, scene,
      family, tag_size_m, distance_m, phi_deg, tilt_axis_deg, roll_deg, image_x, image_y,
      black_square_px, detector, detected_right_id, wrong_id, orientation_error_deg (the angle of
      R_est^T R_true), distance_error_m and distance_error_percent (| |t_est| - |t_true| |),
      corner_rms_px, decision_margin (of the right-id detection: ours 0..1, libapriltag on its own
      scale, aruco none), ms (empty errors: not detected)
  *_summary.csv  per step (or condition and strength) and detector: detection rate with its Wilson 95 %
      interval, frames with a wrong id, median, 10th and 90th percentile of the errors, median time
  *.json         the settings, the conditions' definitions, the render report and any failed frames
  sixdof.csv     as above, plus after black_square_px: halton_index, k1, k2, p1, p2, k3,
      defocus_sigma_px, noise_sigma, quantization_bits (image_x, image_y: the tag centre in the
      distorted image); sixdof_summary.csv: per variable, bin and detector (variable "all": every frame)
Plots: /usr/bin/python3 scripts/plot_raytrace.py DIR; sixdof: scripts/plot_sixdof.py DIR. A frame that fails to render is reported on
stderr and left out; the run goes on.
)";


}  // namespace

int cmd_raytrace(const Words& w) {
  if (wants_help(w, kRaytraceHelp)) return 0;
  const Args a(w, {{"trials"}, {"tag-size"}, {"seed"}, {"detectors"}, {"family"}, {"scene"}, {"distance"}, {"angles"},
                   {"distances"}, {"conditions"}, {"processes"}, {"cache"}, {"povray"}, {"out"}, {"external-timeout"},
                   {"frames"}, {"distance-range"}, {"phi-max"}, {"lens"}, {"defocus-max"}, {"noise-max"}, {"bins"}});
  if (a.positionals().empty()) throw UsageError("which experiment? angle, distance, conditions or sixdof");
  if (a.positionals().size() > 1) throw UsageError("unexpected argument '" + a.positionals()[1] + "'");
  SweepSettings base;
  if (a.has("detectors"))
    parse_detector_list("--detectors", *a.get("detectors"), a.get_double("external-timeout", 1800, 1e-3, 1e9), base);
  else if (a.has("external-timeout"))
    throw UsageError("--external-timeout: no external detector (--detectors ...,external:NAME=COMMAND)");
  const SweepSettings s = parse_sweep_settings(a.positionals()[0], a, std::move(base));
  const std::string exp = experiment_name(s.experiment);
  const RenderOptions ro = render_options(a);
  const std::filesystem::path out = a.get_or("out", "results");
  check_out_folder("--out", out.string());  // before any rendering

  const SweepResult r = run_sweep_with_progress(s, ro, "tagbench raytrace", "raytrace " + exp);

  const std::string stem = result_stem(s);
  const bool made_out = std::filesystem::create_directories(out);
  remove_stale_temporaries(out);  // of a run killed while it wrote these files
  try {
    // The rows, their summary and the settings together or none of them.
    write_files_atomic({{out / (stem + ".csv"), rows_csv(r)},
                        {out / (stem + "_summary.csv"), summary_csv(r, summarize(r))},
                        {out / (stem + ".json"), sidecar_json(r)}});
  } catch (...) {
    std::error_code ec;
    if (made_out) std::filesystem::remove(out, ec);  // only if still empty: a failed run leaves no folder
    throw;
  }
  std::fprintf(stderr,
               "tagbench raytrace %s: %zu frames (%zu distinct: %zu rendered, %zu from the cache, %zu failed) x %zu "
               "detectors; wrote %s.csv, %s_summary.csv, %s.json in %s\n",
               exp.c_str(), r.frames.size(), r.distinct_frames, r.rendered, r.from_cache,
               r.distinct_frames - r.rendered - r.from_cache,
               s.detectors.size(), stem.c_str(), stem.c_str(), stem.c_str(), out.string().c_str());
  return 0;
}

}  // namespace tagbench::cli
