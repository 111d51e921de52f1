#pragma once
// The detectors compared in the localization experiments, behind one interface, every result in our
// conventions (README "Conventions"): corners are the black square's printed top-left, top-right,
// bottom-right, bottom-left with pixel centres at integer coordinates; a pose (R, t) maps tag points
// (origin at the centre, x toward the printed right edge, y toward the bottom edge, z into the tag)
// into the camera frame (x right, y down, z forward), metres.
//
//   tagbench         our detector's default profile (detect/detector.hpp), full resolution
//   tagbench-half    the default profile finding quads at half resolution
//   tagbench-paper   the paper's detector (DetectorOptions::paper()), full resolution
//   tagbench-paper-half  the paper's detector segmenting at half resolution
//   tagbench-thorough  the thorough profile (DetectorOptions::thorough(): the default plus the line
//                    quads), full resolution. Not in the localization sweeps (comparator_names): make
//                    bench runs it on the realistic set, the speed sets and the false-positive corpus.
//   NAME/KEY=V/...   one of the five with options changed, for experiments (detector_variants.hpp)
//   libapriltag-d1   AprilTag 3.3 (libapriltag), quad_decimate 1, nthreads 1, its other defaults
//                    (refine_edges 1, decode_sharpening 0.25, 2 corrected bits); pose by its estimate_tag_pose
//   libapriltag-d2   the same at quad_decimate 2 (its default)
//   aruco            OpenCV 4.6 aruco, DICT_APRILTAG_<family>, CORNER_REFINE_APRILTAG; pose as
//                    estimatePoseSingleMarkers computes it (its marker corners and frame), by
//                    cv::solvePnP with SOLVEPNP_IPPE_SQUARE
//   aruco-default    the same with all of aruco's defaults (CORNER_REFINE_NONE, which also changes
//                    how candidates are found): the false-positive experiments' "as users run it".
//                    Not in the localization sweeps (comparator_names), which compare refined corners.
//
// The conversions (each proved on ray-traced frames by tests/test_comparators.cpp):
//   libapriltag: corners in "pixel i covers [i, i+1)": minus 0.5. Its p[0..3] wrap the tag
//     counter-clockwise as seen in the image starting at the printed bottom-left: (BL, BR, TR, TL), so
//     ours are p[3], p[2], p[1], p[0]. estimate_tag_pose gets the principal point in its own pixel
//     convention (cx + 0.5, cy + 0.5); its tag frame is ours (x right, y down, z into the tag), so R, t
//     are taken as they are.
//   aruco: corners with CORNER_REFINE_APRILTAG in the [i, i+1) convention: minus 0.5 (with the
//     default CORNER_REFINE_NONE they are at pixel centres already: no shift). Its AprilTag
//     dictionaries hold the official tags turned 180 degrees, so its corner 0 (top-left of its marker)
//     is our printed bottom-right: ours are c[2], c[3], c[0], c[1]. Its marker frame has x toward its
//     marker's right, y toward its top, z out of the face; with the 180-degree turn, X_aruco =
//     diag(-1, 1, -1) X_ours, so R_ours = R_aruco diag(-1, 1, -1) and t is the same point (the centre).
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "detect/explain_loss.hpp"
#include "detect/homography.hpp"
#include "detect/pose.hpp"
#include "raytrace/render.hpp"

namespace cv {
class Mat;
}

namespace tagbench::bench {

struct Found {
  std::string family;
  int id = -1;
  int hamming = -1;           // bits corrected; -1 when the detector does not report it (aruco: exact matches only)
  // How clearly the payload was read; NaN when the detector does not say (aruco). The scales differ:
  // ours is Detection::decision_margin (0 = a cell on its threshold, 1 = every cell clear; the
  // minimum over the cells), libapriltag's is its own decision_margin (apriltag.h: the average
  // difference between a data bit's intensity and the decision threshold, on its own scale).
  double decision_margin = std::numeric_limits<double>::quiet_NaN();
  Corners corners;            // our convention (above)
  std::optional<Pose> pose;   // our frames; when the camera and the tag size were given
};

struct DetectorOutput {
  std::vector<Found> found;
  double ms = 0;  // wall time of detection and pose estimation (and the conversions), this thread
};

struct ComparatorSetup {
  std::string family = "36h11";            // one family; libapriltag and aruco know 16h5, 25h9, 36h10, 36h11
  std::optional<CameraIntrinsics> camera;  // with tag_size > 0: poses (pixel centres at integers)
  double tag_size = 0;                     // black square, metres
  // OpenCV's k1, k2, p1, p2, k3 of the camera, for the pose: ours undistorts its corners and aruco's
  // solvePnP takes them; libapriltag's estimate_tag_pose has no distortion model and ignores them.
  std::optional<std::array<double, 5>> distortion;
  // The images' encoding gamma (DetectorOptions::input_gamma, whose own default is 1; ours only): the
  // benchmarks tell our detector each set's encoding, as they tell every detector the camera. 2.2 for
  // photographs (the corpus); the realistic set's camera gamma (realistic_run.cpp); 1 for the
  // ray-traced frames (POV-Ray writes them linear, File_Gamma=1.0) and the synthetic scenes (drawn linear).
  double input_gamma = 2.2;
};

class Comparator {
 public:
  virtual ~Comparator() = default;
  const std::string& name() const { return name_; }
  // Detects in an 8-bit gray image and times it. Not thread-safe: one object per thread. For
  // single-threaded timings call cv::setNumThreads(1) first (aruco uses OpenCV's thread pool).
  DetectorOutput run(const cv::Mat& gray8);
  // Why the tag `family` `id` whose black square is at `truth` (printed TL, TR, BR, BL, pixels) was not
  // reported in this image: the stage where it was lost (detect/explain_loss.hpp), found by detecting
  // again with a trace (untimed: the sweeps ask only about missed frames, after timing them). nullopt
  // when this detector cannot say (can_explain() false: libapriltag, aruco) or does not know the family.
  virtual std::optional<LossExplanation> explain(const cv::Mat& gray8, const std::string& family, int id,
                                                 const Corners& truth);
  virtual bool can_explain() const { return false; }

 protected:
  explicit Comparator(std::string name) : name_(std::move(name)) {}
  virtual std::vector<Found> detect(const cv::Mat& gray8) = 0;

 private:
  std::string name_;
};

// The localization sweeps' detectors: "tagbench", "tagbench-half", "tagbench-paper",
// "tagbench-paper-half", "libapriltag-d1", "libapriltag-d2", "aruco".
const std::vector<std::string>& comparator_names();
// Every name make_comparator knows: the above, "tagbench-thorough" and "aruco-default" (and ours'
// variants, below). is_ours_variant: true for one of our five names followed by "/KEY=VALUE..." (an
// experiment's variant; make_comparator checks the keys).
bool is_ours_variant(const std::string& name);
const std::vector<std::string>& known_comparator_names();

// Throws std::invalid_argument for an unknown name, a family the detector does not support, or a
// camera without a valid tag size.
std::unique_ptr<Comparator> make_comparator(const std::string& name, const ComparatorSetup& setup);

// A detection against the ground truth: the per-frame measures.
struct FoundErrors {
  double corner_rms_px = 0, corner_max_px = 0;  // over the four corners, in printed order
  // With a pose (NaN otherwise): the angle of R_est^T R_true; | |t_est| - |t_true| | in metres and in % of |t_true|.
  double orientation_deg = 0, distance_m = 0, distance_percent = 0;
};
FoundErrors found_errors(const Found& found, const GroundTruth& truth);

}  // namespace tagbench::bench
