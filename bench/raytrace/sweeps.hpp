#pragma once
// The localization experiments of issue 4 (paper section VI-B, Figs. 9 and 10, and beyond them):
// ray-traced frames planned from a seed, rendered through render_frames (cached), modified in image
// space where a condition asks for it, and run through every selected detector (comparators.hpp);
// one row per frame and detector, and per-step summaries.
//
//   angle       (Fig. 9)  the tag at a fixed distance (default 1 m; a 0.166 m black square is then
//                         66 px wide face-on), the angle phi between its normal and the direction to
//                         the camera stepped 0..85 degrees; random tilt axis, in-plane rotation, id and
//                         image position (within 100 px of the centre), the same draws at every step.
//   distance    (Fig. 10) face-on (phi = 0), a 1 m tag by default, 2..10 m in 1 m steps then 12.5..60 m
//                         in 2.5 m steps; random in-plane rotation, id and image position (within 20 px).
//                         1 m is left out: a 1 m black square at 1 m is 400 px, the whole image.
//   conditions  (beyond)  a base frame per trial (1 m, phi uniform in 0..30 degrees, random axis,
//                         rotation, id, position within 100 px) under six conditions, each at four
//                         strengths and a zero-strength baseline that is the plain frame itself:
//                         noise, blur, gradient, occlusion, bent, distortion (condition_table()).
//   sixdof      (beyond)  the FMAC protocol's 6-DoF sweep (arXiv 2601.07723): `trials` frames, each a
//                         scrambled Halton point (halton.hpp) of distance, phi, tilt axis, roll and the
//                         tag centre's image position x and y, plus the frame's defocus and noise, seen
//                         by a camera closer to a real one (CameraEffects: OpenCV lens distortion,
//                         Gaussian defocus, sensor noise, 8-bit quantization). Points whose whole tag
//                         would not be in view are skipped (sixdof_fits); see SixdofSettings.
//
// Randomness: every trial's draws come from splitmix64 seeded by (seed, experiment, trial), so a frame
// does not depend on the steps or the other trials requested, and identical settings give identical
// frames and rows (all but the timing column).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "external/external_detector.hpp"
#include "raytrace/comparators.hpp"
#include "raytrace/loss_columns.hpp"
#include "raytrace/render.hpp"

namespace cv {
class Mat;
}

namespace tagbench::bench {

enum class Experiment { kAngle, kDistance, kConditions, kSixdof };
const char* experiment_name(Experiment e);  // "angle", "distance", "conditions", "sixdof"

enum class Condition { kNone, kNoise, kBlur, kGradient, kOcclusion, kBent, kDistortion };

struct ConditionInfo {
  Condition condition;
  const char* name;         // "noise", "blur", "gradient", "occlusion", "bent", "distortion"
  const char* unit;         // what a strength is
  const char* description;  // how it is made
  std::vector<double> strengths;  // the zero-strength baseline first
};
// The six conditions, in this order: noise, blur, gradient, occlusion, bent, distortion.
const std::vector<ConditionInfo>& condition_table();
const ConditionInfo& condition_info(Condition c);
const char* condition_name(Condition c);  // "none" for kNone
// Throws std::invalid_argument "unknown condition 'x' (noise, blur, ...)".
Condition parse_condition(const std::string& name);
// Throws std::invalid_argument "unknown scene 'x' (plain, realistic)".
SceneKind parse_scene(const std::string& name);
// Throws std::invalid_argument "unknown experiment 'x' (angle, distance, conditions, sixdof)".
Experiment parse_experiment(const std::string& name);

// The 6-DoF sweep's ranges and camera (defaults for the 0.166 m tag and the 400 x 400, f = 400 px
// camera every sweep renders with: the black square is 133 px wide at 0.5 m, 11 px at 6 m).
struct SixdofSettings {
  double distance_min = 0.5, distance_max = 6;  // metres: distance uniform in [min, max]
  double phi_max_deg = 80;                      // phi uniform in [0, this], < 90
  // OpenCV's k1, k2, p1, p2, k3: a mild barrel lens with a little decentring, as a calibrated webcam
  // might have; r = 0.7 (the image corner) moves 8 % inward.
  std::array<double, 5> distortion{-0.2, 0.05, 0.001, -0.0005, 0};
  double defocus_max_px = 1.5;  // defocus: Gaussian sigma uniform in [0, this] pixels
  double noise_max = 4;         // sensor noise: Gaussian sigma uniform in [0, this] 8-bit levels
  double margin_px = 2;         // the whole printed tag this far inside the image (sixdof_fits)
  int bins = 10;                // summaries and plot: bins per variable
};

// resolve_settings' ceilings: trials (sixdof: frames) per step, and distances in metres.
inline constexpr int kMaxSweepTrials = 1000000;
inline constexpr double kMaxSweepDistance = 1e6;

struct SweepSettings {
  Experiment experiment = Experiment::kAngle;
  int trials = 5;                          // frames per step, > 0; sixdof: frames
  std::optional<double> tag_size;          // black square, metres; default 0.166 (angle, conditions), 1 (distance)
  std::uint64_t seed = 1;
  std::vector<std::string> detectors;      // comparator names and external detectors' names, in the rows'
                                           // order; empty: all five, then the external ones
  std::vector<ExternalDetector> external;  // detectors outside the build (external_detector.hpp), by name
  SceneKind scene = SceneKind::kPlain;
  std::vector<double> steps;               // angle: phi in degrees, [0, 90); distance: metres, > 0; empty: defaults
  std::optional<double> distance;          // angle and conditions: the fixed distance, metres (default 1)
  std::vector<Condition> conditions;       // conditions: which; empty: all six
  std::string family = "36h11";            // the one family all five detectors know; libapriltag and aruco
                                           // also know 16h5, 25h9, 36h10, ours every family
  SixdofSettings sixdof;                   // sixdof only (ignored by the others)
};

// The settings with every default filled in; throws std::invalid_argument with a one-line message for
// anything out of range (trials <= 0, an angle outside [0, 90), a distance or tag size <= 0, an unknown
// or repeated detector, steps given to conditions, a distance given to the distance sweep, ...).
SweepSettings resolve_settings(const SweepSettings& settings);
// The external detector of that name, or nullptr.
const ExternalDetector* find_external(const SweepSettings& settings, const std::string& name);
std::vector<double> default_steps(Experiment e);
double position_radius_px(Experiment e);  // how far from the image centre the tag centre may be placed

// What is done to a rendered frame before the detectors see it (noise, blur, gradient, distortion);
// occlusion and bent are rendered (FramePose::extra_sdl) and need nothing here.
// The sixdof sweep's camera, applied to the pinhole render in this order: lens distortion (the render
// remapped so that the image obeys OpenCV's model, bilinear, border replicated), defocus (Gaussian
// blur), sensor noise (Gaussian, seeded), then quantization to 8 bits (rounded, clipped to 0..255);
// the steps before quantization work on floating-point pixels.
struct CameraEffects {
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3
  double defocus_sigma_px = 0;
  double noise_sigma = 0;              // 8-bit levels
  std::uint64_t noise_seed = 0;
  int quantization_bits = 8;
};

struct ImageEffect {
  Condition condition = Condition::kNone;
  double strength = 0;
  std::uint64_t seed = 0;      // noise
  double direction_deg = 0;    // gradient: the direction in the image in which the light falls off
  std::optional<CameraEffects> camera;  // sixdof (then condition is kNone)
};

struct SweepFrame {
  Condition condition = Condition::kNone;  // conditions experiment; kNone otherwise
  double step = 0;           // phi (deg), distance (m) or strength (condition_info(c).unit)
  int trial = 0;
  std::uint64_t seed = 0;    // the trial's seed: all its random draws come from it
  ViewSpec view;
  FramePose frame;           // what POV-Ray renders
  GroundTruth truth;         // corners where they are in the image the detectors get (bent: the bent
                             // corners; distortion: distorted); pose: the nominal (unbent) pose
  ImageEffect effect;
  std::uint64_t sample = 0;    // sixdof: the frame's Halton index
  Eigen::Vector2d image_position{0, 0};  // sixdof: the tag centre in the (distorted) image; else view.pixel
};

// Whether the detectors get the render as it is (no effect, or one that is in the render).
bool frame_unmodified(const SweepFrame& f);

// sixdof: the variables a frame was sampled in (the first six are the pose), their units and ranges,
// and a frame's value of each.
struct SixdofVariable {
  const char* name;  // distance_m, phi_deg, tilt_axis_deg, roll_deg, image_x, image_y, defocus_sigma_px, noise_sigma
  double lo, hi;
};
std::vector<SixdofVariable> sixdof_variables(const SweepSettings& resolved);
double sixdof_value(const SweepFrame& f, std::size_t variable);

// OpenCV's lens model: a pinhole pixel (pixel centres at integers) to where the lens puts it, and back
// (cv::undistortPoints, iterated to 1e-12; nullopt when the model folds over and no preimage is
// within 1e-6 px).
Eigen::Vector2d distort_pixel(const Eigen::Vector2d& pinhole, const std::array<double, 5>& d,
                              const CameraIntrinsics& K = render_camera());
std::optional<Eigen::Vector2d> undistort_pixel(const Eigen::Vector2d& distorted, const std::array<double, 5>& d,
                                               const CameraIntrinsics& K = render_camera());
// The black square's corners as cv::projectPoints puts them (TL, TR, BR, BL; pixel centres at integers).
Corners project_corners(const Pose& pose, double tag_size, const std::array<double, 5>& d,
                        const CameraIntrinsics& K = render_camera());
// sixdof's rule for "the tag in view": the whole printed tag (white border included; `printed_size` its
// edge, metres), 16 points along each edge, is at least `margin_px` inside the image both in the
// pinhole render (where its pixels come from) and through the lens.
bool sixdof_fits(const Pose& pose, double printed_size, const std::array<double, 5>& d, double margin_px);

// The frames of an experiment (settings resolved first), in order step (or condition and strength),
// then trial. Throws std::invalid_argument when a frame's whole printed tag would not be inside the
// image ("the tag does not fit ...").
std::vector<SweepFrame> plan_sweep(const SweepSettings& settings);

// The angle between a pose's tag normal (out of the printed face, -z) and the direction to the camera.
double view_angle_deg(const Pose& pose);

// The image the detectors get: the rendered 8-bit gray frame with the frame's effect applied.
cv::Mat apply_effect(const cv::Mat& gray8, const SweepFrame& frame);

struct SweepRow {
  std::size_t frame = 0;     // index into SweepResult::frames
  std::string detector;
  bool detected_right_id = false, wrong_id = false;
  // Of the right-id detection (the one nearest the truth if several); NaN when not detected or no pose.
  double orientation_error_deg, distance_error_m, distance_error_percent, corner_rms_px;
  double decision_margin;    // of that detection, as Found::decision_margin (NaN: not detected, or not reported)
  double ms = 0;             // the detector's time on this frame, one thread
  // Where the tag was lost (detect/explain_loss.hpp) when not detected with the right id; nullopt when
  // detected, or when the detector cannot say (Comparator::can_explain). CSV: loss_stage, loss_bits.
  std::optional<LossExplanation> loss;
};

struct FailedFrame {
  std::size_t frame = 0;
  std::string error;         // one line
};

struct SweepResult {
  SweepSettings settings;    // resolved
  std::vector<SweepFrame> frames;
  std::vector<SweepRow> rows;  // frame order, then detector order; none for frames that failed to render
  std::vector<FailedFrame> failed;
  std::vector<bool> can_explain;  // per settings.detectors: gives its missed frames a loss stage
  std::size_t distinct_frames = 0, rendered = 0, from_cache = 0;  // distinct renders (as RenderReport)
  int povray_runs = 0;
  double render_seconds = 0, detect_seconds = 0;
};

struct SweepProgress {
  std::function<void(std::size_t done, std::size_t total)> render;  // frames rendered (or failed) of those missing
  std::function<void(std::size_t done, std::size_t total)> detect;  // frames through every detector
  std::function<void(const SweepFrame&, const std::string& error)> failed;  // a frame that did not render
};

// Plans, renders (render_options.progress is replaced by progress.render), and runs every detector on
// every frame in this thread with OpenCV at one thread (restored afterwards). Detectors that accept lens
// distortion get the distortion condition's (sixdof: its lens') coefficients: ours (DetectorOptions::distortion) and aruco
// (its pose, cv::solvePnP IPPE_SQUARE as estimatePoseSingleMarkers with distCoeffs); libapriltag's
// estimate_tag_pose has no distortion model and gets the pinhole intrinsics only. A frame that fails to
// render is reported (progress.failed, SweepResult::failed) and the run goes on; when none renders,
// std::runtime_error. Invalid settings: std::invalid_argument; povray missing: std::runtime_error
// "povray not found: install the Debian package povray".
SweepResult run_sweep(const SweepSettings& settings, RenderOptions render_options, const SweepProgress& progress = {});

// How a frame is scored (the sweeps and tagbench score): a detection of another id (or family) marks
// a wrong id; of the right-id detections the one nearest the truth (corner RMS) gives the errors and
// is returned through `best` (nullptr when none). The loss columns are left empty.
SweepRow score_frame(std::span<const Found> found, double ms, const std::string& detector, std::size_t index,
                     const SweepFrame& frame, const Found** best = nullptr);

// Per (condition, step, detector): the summary; sixdof: per (variable, bin, detector), each
// variable's range cut into settings.sixdof.bins equal bins, and per detector over all frames ("all"). Percentiles are over the frames detected with
// the right id (linear interpolation between order statistics, numpy's default); NaN when none.
struct ErrorStats {
  double median, p10, p90;
};
struct SummaryRow {
  Condition condition = Condition::kNone;
  double step = 0;           // sixdof: the bin's lower edge
  std::string variable;      // sixdof: the binned variable (sixdof_variables), or "all"
  double bin_hi = 0;         // sixdof: the bin's upper edge
  std::string detector;
  int frames = 0, detected = 0, wrong_id_frames = 0;
  double detection_rate = 0, rate_lo95 = 0, rate_hi95 = 0;  // Wilson score interval (bench/stats.hpp)
  double black_square_px_median = 0, ms_median = 0;
  ErrorStats orientation_deg, distance_m, distance_percent, corner_rms_px;
  LossCounts lost;  // missed frames by the stage where the tag was lost (loss_columns.hpp)
};
std::vector<SummaryRow> summarize(const SweepResult& result);

// The q-quantile (0..1) of values, linear interpolation; NaN for none.
double quantile(std::vector<double> values, double q);

// The files the CLI writes: rows (one per frame and detector), summaries, and a JSON sidecar with the
// settings, the conditions' definitions and the render report.
std::string rows_csv(const SweepResult& result);
std::string summary_csv(const SweepResult& result, const std::vector<SummaryRow>& summary);
std::string sidecar_json(const SweepResult& result);
// "fig9_angle", "fig10_distance", "conditions", "sixdof": the files' stem.
const char* result_stem(Experiment e);
// The stem of a run's files: result_stem(experiment), plus "_" and the family when it is not 36h11
// (the family of the paper's figures), so that sweeps of other families sit beside the 36h11 ones
// without overwriting them: fig10_distance_16h5.csv. A family file is named by its file name without
// extension; characters other than letters, digits, '-' and '_' become '_'.
std::string result_stem(const SweepSettings& s);

}  // namespace tagbench::bench
