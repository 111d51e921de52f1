#pragma once
// The detectors on the realistic set (issue 17, part 3): every named detector (comparators.hpp) on
// every frame, one thread, each truth tag scored per detector; per tag-size bin, detection rates with
// Wilson 95 % intervals, wrong and false detections, corner errors.
//
// Scoring. A detection of the truth tag's family and id whose four corners (printed order) lie within
// an RMS of max(2 px, 0.2 x the black square) of the truth detects that tag (the nearest one, if
// several). Every other detection is false; a false detection whose centre lies in a truth tag's black
// square is that tag's wrong id. False detections are binned by their own size (sqrt of the quad's area).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "raytrace/comparators.hpp"
#include "raytrace/loss_columns.hpp"
#include "realistic/realistic_set.hpp"

namespace tagbench::bench {

struct RealisticRunSettings {
  RealisticSettings set;               // the frames (seed, family, camera, ...)
  int frames = 200;                    // frames 0 .. frames-1 of the set, > 0
  std::vector<std::string> detectors;  // make_comparator names; empty: comparator_names() (the five)
};

// The tag-size bins (black square px, sqrt of area): [12,16) [16,20) [20,24) [24,28) [28,32) [32,40],
// with "below" and "above" bins for sizes outside 12..40 (only present when a tag falls there).
struct SizeBin {
  std::string name;  // "12-16", ..., "32-40", "<12", ">40"
  double lo = 0, hi = 0;
};
const std::vector<SizeBin>& size_bins();
const SizeBin& size_bin_of(double black_square_px);

struct RealisticFrameInfo {  // a frame without its pixels
  int index = 0;
  std::uint64_t frame_seed = 0;
  int width = 0, height = 0;
  CameraIntrinsics camera;
  CameraDegradation degradation;
  std::vector<RealisticTag> tags;
};

struct TagScore {
  std::size_t frame = 0, tag = 0;  // indices into RealisticResult::frames and its tags
  std::string detector;
  bool detected = false, wrong_id = false;
  double corner_rms_px, decision_margin;  // of the detection; NaN when not detected (margin: also when not reported)
  double ms = 0;                          // the detector's time on the whole frame, one thread
  // Where a missed tag was lost (loss_columns.hpp); nullopt when detected or the detector cannot say.
  std::optional<LossExplanation> loss;
};

struct RealisticFalseDetection {
  std::size_t frame = 0;
  std::string detector, family;
  int id = -1;
  double size_px = 0;                // sqrt of the detected quad's area
  Eigen::Vector2d centre{0, 0};
  int at_tag = -1;                   // the truth tag whose black square holds its centre (a wrong id), or -1
};

struct RealisticResult {
  RealisticRunSettings settings;     // resolved (detectors filled in)
  std::vector<RealisticFrameInfo> frames;
  std::vector<TagScore> scores;      // frame, tag, then detector order
  std::vector<RealisticFalseDetection> false_detections;
  std::vector<bool> can_explain;     // per settings.detectors (Comparator::can_explain)
  double generate_seconds = 0, detect_seconds = 0;
};

// The set's scoring of one detector's output on one frame: for each tag, in order, the detection that
// detects it (the tag's family and id, corners within an RMS of max(2 px, 0.2 x its black square); the
// nearest such, each detection taken by one tag at most), as an index into `found`, or -1.
struct TagMatch {
  int found = -1;
  double corner_rms_px = std::numeric_limits<double>::quiet_NaN();  // of that detection; NaN when none
};
std::vector<TagMatch> match_tags(std::span<const RealisticTag> tags, std::span<const Found> found);

// Throws std::invalid_argument (one line) for bad settings or an unknown or repeated detector.
RealisticRunSettings resolve_run_settings(const RealisticRunSettings& settings);

// `on_frame` (optional) sees every frame with its pixels (export); `progress` after every frame.
RealisticResult run_realistic(const RealisticRunSettings& settings,
                              const std::function<void(const RealisticFrame&)>& on_frame = {},
                              const std::function<void(std::size_t done, std::size_t total)>& progress = {});

struct RealisticSummaryRow {
  std::string bin;                   // a size_bins() name, or "all"
  double bin_lo = 0, bin_hi = 0;
  std::string detector;
  int tags = 0, detected = 0, wrong_id_tags = 0, false_detections = 0;
  double rate = 0, rate_lo95 = 0, rate_hi95 = 0;
  double corner_rms_px_median, corner_rms_px_p90;  // over the detected tags; NaN when none
  LossCounts lost;                   // missed tags by the stage where they were lost
};
// Bin order (the used bins, then "all"), detector order within a bin.
std::vector<RealisticSummaryRow> summarize_realistic(const RealisticResult& result);

// The files: rows (a row per tag and detector), false detections, summary, JSON sidecar.
std::string realistic_rows_csv(const RealisticResult& result);
std::string realistic_false_csv(const RealisticResult& result);
std::string realistic_summary_csv(const RealisticResult& result, const std::vector<RealisticSummaryRow>& summary);
std::string realistic_sidecar_json(const RealisticResult& result, const std::vector<RealisticSummaryRow>& summary);

}  // namespace tagbench::bench
