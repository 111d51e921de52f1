#pragma once
// Scoring any detector's output on an exported dataset (issue 12, section 2), exactly as the sweeps
// score the built-in detectors (sweeps.hpp: the same rows, summaries and files).
//
// Detections: JSON lines, one per image, in any order:
//   {"image": "FILE", "ms": 1.2 (optional), "detections": [{"family": "36h11", "id": 7,
//     "corners": [[x, y] x4], "pose": {"R": [[3] x3], "t": [x, y, z]} (optional),
//     "decision_margin": m (optional), "hamming": k (optional)}]}
// ("error": "message" in place of "detections": the detector failed on that image.)
// FILE is the frame's file name as truth.json gives it, or a path to it (relative or absolute).
//
// A detector with another convention is declared (Convention) and converted into ours (README
// "Conventions"); when its corners or poses fit the truth far better under another declaration, the
// scorer names the options that would fix it (convention_hint).
#include <array>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dataset/dataset.hpp"
#include "external/detection_lines.hpp"
#include "raytrace/comparators.hpp"

namespace tagbench::bench {

// How a detector's numbers relate to ours.
struct Convention {
  // order[k]: which of our corners (0 TL, 1 TR, 2 BR, 3 BL) the detector's k-th corner is.
  std::array<int, 4> order{0, 1, 2, 3};
  // The detector's coordinate of a pixel centre minus ours (0.5: "pixel i covers [i, i+1)").
  double pixel_offset = 0;
  // Row i: the detector's tag axis i in our tag frame (a signed permutation, determinant +1); the
  // origin is the tag centre in both. R_ours = R_theirs * tag_axes.
  Eigen::Matrix3d tag_axes = Eigen::Matrix3d::Identity();
};

// "tl-tr-br-bl" (ours), "bl-br-tr-tl", ...: the four corner names in the detector's order. Throws
// std::invalid_argument naming the text.
std::array<int, 4> parse_corner_order(const std::string& text);
std::string corner_order_name(const std::array<int, 4>& order);
// "x,y,z" (ours), "-x,y,-z" (aruco's marker frame), ...: the detector's x, y, z axes in ours.
Eigen::Matrix3d parse_tag_frame(const std::string& text);
std::string tag_frame_name(const Eigen::Matrix3d& axes);

// A detection in our convention.
Found to_ours(const Found& theirs, const Convention& c);

struct ScoreResult {
  SweepResult sweep;          // settings: the dataset's, detectors = {name}; frames: the dataset's, in order
  std::vector<std::size_t> plan_index;  // per frame: its index in the sweep's plan (truth.json "index")
  std::string hint;           // one line when another declared convention fits far better, else empty
};

// Every frame of the dataset must have exactly one line, and every line name a frame: otherwise
// std::runtime_error "SOURCE: ..." naming the image. `dataset_dir` resolves image paths.
ScoreResult score_detections(const Dataset& dataset, const std::filesystem::path& dataset_dir,
                             const std::vector<ImageDetections>& lines, const std::string& source,
                             const std::string& name, const Convention& convention);

// The one-line advice (empty when none): tries the corner orders (the four rotations and their
// reversals), half-pixel shifts and the 24 tag-frame rotations on the right-id detections, and names
// the declaration that fits the truth far better than the given one.
std::string convention_hint(const std::vector<std::pair<Found, const SweepFrame*>>& matched,
                            const Convention& declared, const std::string& name);

// The sidecar written beside the rows and summary (the keys plot_raytrace.py reads, and what was scored).
std::string score_sidecar_json(const ScoreResult& r, const std::filesystem::path& dataset,
                               const std::string& detections, const Convention& convention);

}  // namespace tagbench::bench
