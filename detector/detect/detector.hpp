#pragma once
// The paper's detector (sections III and IV) as one object: image -> gradients -> clusters ->
// segments -> quads -> decoded tags -> poses. Every stage is its own unit (blur, gradient,
// segmentation, line_fit, quad_search, homography, payload_decode, pose); the pipeline is the
// composition of four functions over them, each in its own file:
//   find_quads_in_image   stages 1-5: blur (and halve), gradients, clusters, segments, quads
//   decode_quads          stage 6: border pre-filter, payload readings, the best family's decode
//   suppress_duplicates   one detection per tag; then drop_below_margin (min_decision_margin)
//   estimate_poses        stage 7: undistort, pose
// Detector::detect is that list of calls plus timings and the trace; another detector profile is
// another composition of these (or other options of a stage), not a branch inside it. The options
// and the profiles (DetectorOptions, paper(), thorough()) are in detector_options.hpp.
//
// Conventions: pixel centres at integer coordinates; camera frame x right, y down, z forward; tag
// frame origin at the centre, x toward the printed right edge, y toward the bottom edge, z into the
// tag; pose (R, t) maps tag points into the camera frame (metres); tag size = the black square's
// edge; corners are the black square's outer corners in the order top-left, top-right,
// bottom-right, bottom-left of the printed tag.
#include <array>
#include <memory>
#include <optional>
#include <string_view>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "../codes/tag_family.hpp"
#include "boundaries.hpp"
#include "detector_options.hpp"  // DetectorOptions and the profiles
#include "image.hpp"
#include "line_fit.hpp"
#include "payload_decode.hpp"
#include "pose.hpp"
#include "quad_search.hpp"
#include "segmentation.hpp"
#include "threshold.hpp"

namespace tagbench {

struct StageTimings {  // milliseconds, for the whole frame
  double blur = 0, gradient = 0, segmentation = 0, line_fit = 0, quads = 0, decode = 0, pose = 0, total = 0;
  std::size_t segment_count = 0, quad_count = 0;  // what the stages produced (candidate quads before decoding)
};

struct Detection {
  std::string family;
  int id = -1, hamming = 0, rotation = 0;
  Corners corners;                   // printed order TL, TR, BR, BL; pixels, as observed (distorted image)
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Matrix3d homography = Eigen::Matrix3d::Identity();  // tag square [-1,1]^2 (printed axes) -> image
  double decision_margin = 0;        // payload_decode.hpp: 0 = a bit on its threshold, 1 = every bit clear
  double observed_perimeter = 0;     // px, the four fitted segments' lengths
  std::optional<PoseSolution> pose;              // best pose, when camera and tag size are given
  std::optional<PoseSolution> pose_alternative;  // the planar ambiguity's other solution, if any
  // The image could not tell the two solutions apart: their pattern correlations differ by less than
  // PoseChoiceOptions::ambiguous_correlation_gap (both fit the corners). `pose` may then be the wrong
  // one of the two: a user needing the orientation should treat it as unknown up to the alternative.
  bool pose_ambiguous = false;
  StageTimings timings;              // of the frame this detection came from
};

// What became of one candidate quad in decoding (decode_quads.hpp), for explaining a lost tag
// (explain_loss.hpp).
struct QuadOutcome {
  enum class Fate {
    kBorderRejected,  // the border pre-filter (PayloadOptions::quick_reject) refused it
    kNoHomography,    // degenerate corners
    kUnreadable,      // no payload width could be read (cells outside the image, no border contrast)
    kNotDecoded,      // read, but no family decoded it within max_hamming
    kDecoded,         // became a detection (before duplicate and overlap suppression and the margin filter)
    // Decoded within its family's correction, but with more bits corrected than the stage that made
    // the quad accepts (the line quads: LineQuadOptions::spare_bits fewer, exact readings kept with
    // keep_exact); not reported. The fallbacks that take undecoded quads (code refit, bent reading)
    // leave it alone, as when decoded.
    kTooFarForItsSource,
  };
  Fate fate = Fate::kUnreadable;
  // The bits read per payload width d (index d; nullopt where not read), as seen through the quad.
  std::array<std::optional<Code>, kMaxPayloadWidth + 1> bits{};
  std::string family;  // kDecoded: what it decoded as
  int id = -1, hamming = -1;
  double decision_margin = 0;
};

// Intermediate results for the paper's Fig. 3 and Fig. 4 pictures (tagbench detect --debug-dir) and
// for explaining why a tag was not reported (explain_loss.hpp).
struct DetectorTrace {
  ImageF segmentation_input;  // blurred (and halved) image the gradients came from
  double segmentation_scale = 1;  // input pixels per segmentation_input pixel (2 when halved)
  ImageF gradient_magnitude, gradient_direction;
  Clusters clusters;              // in segmentation_input's pixels
  std::vector<Segment> segments;  // in full-resolution coordinates
  // The threshold quad finder's (quad_finder kThreshold) main pass, in segmentation_input's pixels:
  // every pixel's class (kTernaryDark, kTernaryLight, kTernaryUnknown: threshold.hpp) and the
  // boundary groups the quads were fitted to (boundaries.hpp: doubled coordinates, one group per
  // pair of dark and light components). Where a tag has no candidate quad these say why: its black
  // square joined to a dark neighbour, its white ring broken or classed dark, its outline split
  // among several groups. Empty for the gradient quad finder.
  TernaryImage threshold_classes;
  BoundaryGroups boundary_groups;
  std::vector<Quad> quads;
  std::vector<PayloadReading> readings;  // one per quad that could be sampled
  std::vector<QuadOutcome> quad_outcomes;  // one per entry of quads, in order
  std::vector<Detection> withdrawn;        // detections the occlusion refit withdrew, as decoded
};

// The per-pixel working buffers of one detection (the float image, blur, gradients, the
// segmentation graph and union-find, the clusters), kept from one frame to the next so that a
// stream of images of one size is processed without reallocating them: pass the same workspace to
// every detect() call. Buffers only grow (to the largest image seen, and for the edge lists, which
// depend on the scene, with a quarter of headroom); release() or destroying the workspace returns
// the memory. The photometric refinement's per-tag buffers live here too (not per image pixel: about
// 300 bytes per pixel it fits, at most max(2500, 25 x the tag's side) of them, so under 1 MB for
// tags up to 100 px; not in buffers()). The Detector stays const and holds no per-call state, so thread safety is the
// caller's by construction: one workspace per thread (a workspace must never be used by two
// detect() calls at once), any number of threads on one Detector. The detect() overloads without a
// workspace use a temporary one, i.e. allocate per call.
class DetectorWorkspace {
 public:
  DetectorWorkspace();
  ~DetectorWorkspace();
  DetectorWorkspace(DetectorWorkspace&&) noexcept;
  DetectorWorkspace& operator=(DetectorWorkspace&&) noexcept;
  DetectorWorkspace(const DetectorWorkspace&) = delete;
  DetectorWorkspace& operator=(const DetectorWorkspace&) = delete;

  // One entry per buffer: where its storage is and how many bytes it can hold. Unchanged from one
  // call to the next means nothing was reallocated (the tests and results/memory.csv use this).
  struct Buffer {
    const char* name;
    const void* data;
    std::size_t capacity_bytes;
  };
  std::vector<Buffer> buffers() const;
  std::size_t capacity_bytes() const;  // sum over buffers()
  void release();                      // frees every buffer

  // The buffers themselves (detect/workspace_impl.hpp), for the pipeline's stages
  // (find_quads_in_image.hpp); a moved-from workspace gets fresh ones.
  struct Impl;
  Impl& impl();

 private:
  std::unique_ptr<Impl> impl_;
};

struct FoundQuads;  // find_quads_in_image.hpp

// Stages 1-5 as a replaceable function (the seam for other detector profiles): find_quads_in_image
// is the paper's; any function over the same types can take its place in the pipeline.
using QuadFinder = FoundQuads (*)(const ImageF& gray, const DetectorOptions& opt, DetectorWorkspace& workspace,
                                  StageTimings* timings, DetectorTrace* trace);

class Detector {
 public:
  // Loads the families (load_family) and validates the options (DetectorOptions::validate); throws
  // std::invalid_argument on a family that cannot be loaded or on a bad option.
  explicit Detector(DetectorOptions options);

  // Detects tags in a float gray image (image.hpp) or an 8-bit gray buffer (ImageU8View, converted
  // into the workspace's float image); cv::Mat input goes through detect/detector_opencv.hpp. Const
  // and thread-safe: any number of threads may call it at once (each with its own workspace, if
  // any). Throws std::invalid_argument for an empty image and for one over options().max_pixels
  // (see there). `timings`, if given, receives the frame's stage timings (also when nothing is detected).
  std::vector<Detection> detect(const ImageF& gray, DetectorTrace* trace = nullptr,
                                StageTimings* timings = nullptr) const;
  std::vector<Detection> detect(const ImageU8View& gray, DetectorTrace* trace = nullptr,
                                StageTimings* timings = nullptr) const;
  // The same, reusing `workspace`'s buffers (see DetectorWorkspace): the results are identical.
  std::vector<Detection> detect(const ImageF& gray, DetectorWorkspace& workspace, DetectorTrace* trace = nullptr,
                                StageTimings* timings = nullptr) const;
  std::vector<Detection> detect(const ImageU8View& gray, DetectorWorkspace& workspace, DetectorTrace* trace = nullptr,
                                StageTimings* timings = nullptr) const;

  // Throws std::invalid_argument ("image WxH (N pixels) is over the detector's limit ...") for an
  // image over options().max_pixels; for entry points that convert an image before detect().
  void check_size(long long width, long long height) const;

  const DetectorOptions& options() const { return opt_; }
  const std::vector<TagFamily>& families() const { return families_; }

 private:
  std::vector<Detection> run(const ImageF& gray, DetectorWorkspace& ws, DetectorTrace* trace,
                             StageTimings* timings) const;

  DetectorOptions opt_;
  std::vector<TagFamily> families_;
  DefocusModels defocus_models_;  // defocus_read.hpp: built once when opt_.defocus_read.enabled
  QuadFinder find_quads_;  // stages 1-5 of this detector's profile
};

}  // namespace tagbench
