#pragma once
// Ray-traced frames for the localization experiments (issue 4; paper section VI-B): a tag at a known
// pose rendered by POV-Ray 3.7 from the templates in raytrace_scenes/, with its ground truth in our
// conventions.
//
// Camera: pinhole, 400 x 400 pixels, f = 400 px, as in the paper. POV-Ray shoots each pixel's ray
// through the pixel's centre and the optical axis between pixels 199 and 200, so with pixel centres at
// integer coordinates the principal point is (199.5, 199.5).
//
// Rendering runs POV-Ray's animation mode: the frames still missing from the cache go into one scene
// file, a #switch (frame_number) with one pose per frame, and frame ranges (+SF/+EF) are spread over
// several povray processes at once. Every frame is cached in a flat directory under a hash of what
// determines its pixels (scene template, pose, family, id, tag cells, tag size, per-frame SDL, render
// settings), written under a temporary name and renamed once it decodes, so an interrupted run resumes
// where it stopped and a rerun renders nothing. POV-Ray dies with the process that started it (a
// kill -9 leaves no povray rendering on), and the next run keeps the frames such a run finished and
// removes its scene, logs and unfinished frames (render_batches.hpp).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "detect/homography.hpp"
#include "detect/pose.hpp"

namespace cv {
class Mat;
}

namespace tagbench::bench {

inline constexpr int kRenderWidth = 400, kRenderHeight = 400;
inline constexpr double kRenderFocalPx = 400;

// fx = fy = 400, principal point (199.5, 199.5).
CameraIntrinsics render_camera();

// The scene templates shipped in raytrace_scenes/ (embedded at build time).
enum class SceneKind {
  kPlain,      // self-lit black-and-white tag on a uniform grey background
  kRealistic,  // a point light, a diffuse tag, a brick wall behind it and a checkered floor
};
const std::string& scene_template(SceneKind kind);
const char* scene_name(SceneKind kind);  // "plain", "realistic"

struct FramePose {
  Pose pose;                     // tag -> camera, metres, our conventions (pose.hpp); t.z() > 0
  std::string family = "36h11";  // a built-in family name or a family file
  // The family's own name (a family file's `name:` header), what detectors report; empty: `family`.
  // Not part of the cache key (the codes come from `family`).
  std::string family_name;
  int id = 0;
  double tag_size = 0.166;       // edge of the black square, metres
  std::string extra_sdl;         // POV-Ray SDL added to this frame's #case (an occluder, ...); part of the cache key
};

// A pose for the sweeps: the tag centre on the ray through image point `pixel`, `distance` metres
// from the camera centre; the tag's normal (its -z axis, out of the printed face) makes the angle
// `phi_deg` with the direction to the camera, tilted about the in-plane axis at `tilt_axis_deg` from
// the tag's x axis; `roll_deg` turns the tag about the viewing ray (in-plane rotation; at phi = 0 and
// the image centre the printed top-left corner goes round clockwise in the image as roll grows).
struct ViewSpec {
  double distance = 1;  // metres, > 0
  double phi_deg = 0;   // [0, 90)
  double tilt_axis_deg = 0;
  double roll_deg = 0;
  Eigen::Vector2d pixel{199.5, 199.5};
};
Pose view_pose(const ViewSpec& view, const CameraIntrinsics& camera = render_camera());

struct GroundTruth {
  Pose pose;
  Corners corners;        // the black square's corners projected: printed TL, TR, BR, BL, pixel centres at integers
  double black_square_px;  // mean edge of the projected black square, pixels
};
GroundTruth ground_truth(const FramePose& frame);

// The frame cache the commands use unless told otherwise: $XDG_CACHE_HOME/tagbench/raytrace, else
// ~/.cache/tagbench/raytrace, else a folder under the system's temporary directory.
std::filesystem::path default_render_cache();

struct RenderOptions {
  std::filesystem::path cache_dir;  // created when missing; flat (POV-Ray only reads and writes its working directory)
  std::string povray = "povray";    // the executable: a name looked up in PATH, or a path
  int processes = 0;                // povray processes at once, each rendering with one thread; <= 0: hardware threads
  int max_frames_per_process = 100; // frames per povray run (an interrupted run loses at most this many per process)
  int nice = 0;                     // niceness added to the povray processes
  // Called after every povray run with the number of frames finished (rendered or failed) and the
  // number to render; from several threads, one call at a time.
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct RenderedFrame {
  std::filesystem::path png;  // the cached frame (8-bit RGB PNG, 400 x 400); empty when it failed
  bool from_cache = false;    // found in the cache, nothing rendered
  std::string error;          // why it failed to render (POV-Ray's message); empty on success
  bool ok() const { return error.empty(); }
};

struct RenderReport {
  std::vector<RenderedFrame> frames;  // one per input frame, in input order
  std::size_t rendered = 0, from_cache = 0, failed = 0;  // distinct frames (duplicates render once)
  int povray_runs = 0;                // povray processes started
  double seconds = 0;                 // wall time
};

// Renders every frame not yet in the cache. A frame that fails to render is reported in its
// RenderedFrame and the others go on. Throws std::invalid_argument for a bad frame (unknown family, id
// out of range, tag_size <= 0, non-finite pose, tag not in front of the camera, a scene template
// without exactly one placeholder), and std::runtime_error "povray not found: install the Debian
// package povray" when something must be rendered and the executable is missing ("povray 'X': not
// an executable file" or "...: no executable of this name in PATH" when options.povray names another).
RenderReport render_frames(const std::vector<FramePose>& frames, const std::string& scene_template,
                           const RenderOptions& options);

// The povray executable `povray` names (a name looked up in PATH, or a path), if it exists.
std::optional<std::filesystem::path> find_povray(const std::string& povray = "povray");

// The cache key of a frame (16 hex digits), as render_frames names its file "frame-KEY.png".
std::string frame_cache_key(const FramePose& frame, const std::string& scene_template);

// A rendered frame as an 8-bit gray image (what the detectors get); throws std::runtime_error if the
// file does not decode.
cv::Mat read_frame_gray(const std::filesystem::path& png);

}  // namespace tagbench::bench
