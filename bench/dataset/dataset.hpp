#pragma once
// Ground-truthed datasets anyone can use without our code (issue 12, section 1): the frames of a
// ray-traced sweep (sweeps.hpp), as the detectors get them (the condition applied), as PNG files, and
// one truth.json describing the camera, the conventions and every frame's truth.
//
// truth.json ("format": "tagbench-dataset 1"):
//   experiment, settings (scene, family, tag_size_m, seed, trials, steps, distance_m, conditions),
//   camera {width, height, fx, fy, cx, cy, distortion [k1,k2,p1,p2,k3] (OpenCV's model; zeros: pinhole)},
//   conventions {pixel_centres "integer", corner_order "tl-tr-br-bl", tag_frame_axes, intensity_gamma 1 (linear), words},
//   frames [{file, index, condition, strength, step, step_unit, trial, seed, family, id, tag_size_m,
//            R [[3] x3], t [3] (tag -> camera, metres), corners [[x,y] x4], black_square_px,
//            distortion (this frame's [k1..k3] when it differs from the camera's, else null),
//            view {distance_m, phi_deg, tilt_axis_deg, roll_deg, image_x, image_y}}],
//   failed [{index, error}] (frames POV-Ray could not render: no file, no truth).
// Numbers are written as the shortest decimal that reads back as the same double, so a dataset read
// back (read_dataset) gives the sweep's frames bit for bit.
#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "raytrace/sweeps.hpp"

namespace tagbench::bench {

inline constexpr const char* kDatasetFormat = "tagbench-dataset 1";

struct DatasetFrame {
  std::string file;   // relative to the dataset folder
  std::size_t index = 0;  // the frame's place in the sweep's plan (plan_sweep)
  SweepFrame frame;   // what the sweep knows of it (view, pose, truth; effect without its image)
  std::optional<std::array<double, 5>> distortion;  // the lens of this frame when not a pinhole
};

struct Dataset {
  SweepSettings settings;            // resolved; detectors empty
  std::vector<DatasetFrame> frames;  // plan order; frames that failed to render are not here
  std::vector<FailedFrame> failed;
};

// The file name of the frame at plan index i: "frame_00042.png".
std::string dataset_frame_file(std::size_t index);

// The frames of a dataset (files) and its truth.json, in memory; `frames` are the PNG files
// (name, bytes), in plan order.
struct DatasetFiles {
  std::vector<std::pair<std::string, std::string>> frames;
  std::string truth_json;
  std::size_t planned = 0, rendered = 0, from_cache = 0, failed = 0;  // as RenderReport (distinct frames)
};

// Plans the sweep (settings.detectors ignored), renders what is missing from the cache
// (render_options.progress reports it), applies each frame's condition and encodes it as an 8-bit gray
// PNG. `frame_done` (optional) is called after each frame is encoded. Throws as run_sweep does
// (std::invalid_argument for bad settings, std::runtime_error when POV-Ray is missing or no frame renders).
DatasetFiles make_dataset(const SweepSettings& settings, const RenderOptions& render_options,
                          const std::function<void(std::size_t done, std::size_t total)>& frame_done = {});

// Writes the files into `dir` (created when missing) as one result: every file is written to a
// temporary first and all are renamed at the end. `dir` must be missing, empty, or an earlier dataset
// (holding a truth.json), whose frames not in the new one are then removed. Throws
// std::runtime_error naming `dir` otherwise.
void write_dataset(const std::filesystem::path& dir, const DatasetFiles& files);

// The truth.json of the frames (in plan order) of resolved `settings`, `failed` left out.
std::string truth_json(const SweepSettings& settings, const std::vector<SweepFrame>& frames,
                       const std::vector<FailedFrame>& failed);

// Reads DIR/truth.json (DIR may also name the truth.json itself). Throws std::runtime_error
// "PATH: what is wrong" (not JSON, another format, a missing or ill-typed field, naming the frame).
Dataset read_dataset(const std::filesystem::path& dir);

}  // namespace tagbench::bench
