// tagbench detect: runs the detector (paper sections III-IV) on images, directories of images and
// videos; prints every detection as JSON or CSV on stdout, optionally draws the detections (the
// paper's Fig. 1) and the intermediate stages (Figs. 3 and 4).
//
// JSON output (the default; one document for the whole run; --help prints the same text):
//
//   {
//     "tool": "tagbench detect",
//     "options": {
//       "families": ["36h11", ...],           // family names, as loaded
//       "max_hamming": 1,                     // bits corrected at most
//       "min_decision_margin": 0,             // detections read with a smaller margin are dropped
//       "half_res": false,                    // segmentation at half resolution
//       "camera": [fx, fy, cx, cy] | null,    // pixels
//       "distortion": [k1, k2, p1, p2, k3] | null,
//       "tag_size": s | null                  // metres, edge of the black square
//     },
//     "images": [                             // every input that was processed, in input order
//       {
//         "input": "path" | "video#frameN",   // N counts from 0
//         "frame": N,                         // video frames only
//         "width": W, "height": H,            // pixels
//         "detect_ms": t,                     // wall time of the detector on this image
//         "detections": [
//           {
//             "family": "36h11", "id": 7, "hamming": 0, "rotation": 0..3,
//             "decision_margin": m,           // 0 = a payload bit on its threshold, 1 = every bit clear
//             "corners": [[x,y],[x,y],[x,y],[x,y]],  // black square's outer corners, printed TL, TR, BR, BL
//             "center": [x, y],
//             "homography": [[h00,h01,h02],[h10,h11,h12],[h20,h21,h22]],  // tag square [-1,1]^2 -> image
//             "pose": {"R": [[..],[..],[..]], "t": [x, y, z], "reprojection_rms_px": e},  // only with
//                                             // --camera/--tag-size: X_cam = R X_tag + t, metres
//             "pose_alternative": {...},      // the planar ambiguity's other solution, when there is one
//             "timings_ms": {"blur", "gradient", "segmentation", "line_fit", "quads", "decode",
//                            "pose", "total"}  // of the whole frame
//           }
//         ]
//       }
//     ],
//     "errors": [{"input": "path", "error": "what went wrong"}]   // inputs that failed, in input order
//   }
//
// Pixel coordinates have pixel centres at integer coordinates; the camera frame is x right, y down,
// z forward; the tag frame has its origin at the tag centre, x toward the printed right edge, y
// toward the bottom edge, z into the tag. Numbers are printed in the shortest form that reads back
// to the same double; a non-finite number is null. Strings are UTF-8; bytes of a path that are not
// valid UTF-8 become U+FFFD.
//
// CSV output (--format csv): a header row, then one row per detection:
//   input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,
//   tx,ty,tz,r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,
//   min_decision_margin
// (pose columns empty without --camera; fields quoted as RFC 4180 when needed).
//
// Decisions: a 1-pixel (or any tiny) image is valid input and has no detections; a missing,
// unreadable, 0-byte or undecodable file, a directory without images and a video without a
// readable frame are errors of that input: one line on stderr, an entry in "errors", the other
// inputs still processed, exit status 1. Bad options are usage errors (exit 2) reported before
// anything is read or written; a family that cannot be loaded exits 1 (as in `tagbench render`).
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/detect_pictures.hpp"
#include "cli/image_file.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/homography.hpp"
#include "detect/image.hpp"
#include "tools/atomic_file.hpp"
#include "tools/format.hpp"
#include "tools/json.hpp"
#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kHelp = R"(usage: tagbench detect IMAGE_OR_DIR_OR_VIDEO... [--family F]... [--max-hamming K]
                       [--min-margin M] [--camera fx,fy,cx,cy] [--distortion k1,k2,p1,p2,k3] [--tag-size M] [--half-res]
                       [--format json|csv] [--draw OUT] [--debug-dir DIR] [--threads T]

Detects tags in every input and prints the detections on stdout, in input order.
Inputs: image files (png, jpg, pgm, tiff, ...; colour and 16-bit are converted to gray), directories
(searched recursively, image extensions only, sorted), videos (.mp4 .avi .mkv .mov .webm .m4v .mpg
.mpeg .wmv .flv .ogv .3gp .ts: every frame, reported as FILE#frameN with N from 0).
  --family F           tag family, a built-in name or a family file; repeatable (default 36h11)
  --max-hamming K      payload bits corrected at most, 0..16 (default 1)
  --min-margin M       drop detections whose decision_margin is below M, 0..1 (default 0: keep all,
                       as the paper). Beyond the paper: against false detections of small families;
                       see results/margin_tradeoff.csv for what each M costs and saves
  --camera fx,fy,cx,cy intrinsics in pixels (fx, fy > 0; cx, cy >= 0); needs --tag-size; adds poses
  --distortion k1,k2,p1,p2[,k3]
                       OpenCV lens distortion; needs --camera (corners are undistorted for the pose)
  --tag-size M         edge of the black square in metres (> 0); needs --camera
  --half-res           segment at half resolution (the paper's faster option)
  --format json|csv    output format (default json)
  --draw OUT           draw the detections like the paper's Fig. 1 (outline, printed top-left corner
                       as a dot, id at the centre, pose axes x red, y green, z blue, tag size / 2 long;
                       z points into the tag). One image input: OUT is the picture (.png, .jpg);
                       otherwise OUT is a directory and each image goes to OUT/<name>.png
                       (<name> = file name without extension, made unique with _2, _3, ...;
                       video frames: <name>_frameN.png)
  --debug-dir DIR      the stages of the paper's Figs. 3 and 4 as DIR/<name>_<stage>.png, stages
                       gradient_magnitude, gradient_direction, clusters (at the segmentation's
                       resolution: half size with --half-res), segments (notch toward the light side),
                       quads (every candidate; dot on its first corner), samples (the detected tags'
                       sample points: white ring white, black ring black, payload yellow)
  --threads T          images processed in parallel (default: all cores); output order is input order

Errors: an input that cannot be read (missing, unreadable, 0 bytes, corrupt) prints one line on stderr
naming it, the other inputs are still processed, and the exit status is 1. Bad options exit with 2.
A 1-pixel image is valid and has no detections. Files are written atomically; nothing is written for
a failed input.

JSON output (one document for the whole run):
  {"tool": "tagbench detect",
   "options": {"families": [names], "max_hamming": K, "min_decision_margin": M, "half_res": bool,
               "camera": [fx,fy,cx,cy] or null, "distortion": [k1,k2,p1,p2,k3] or null,
               "tag_size": metres or null},
   "images": [{"input": path or "video#frameN", "frame": N (videos only), "width": W, "height": H,
               "detect_ms": wall time,
               "detections": [{"family", "id", "hamming", "rotation", "decision_margin",
                               "corners": [[x,y] x4: printed TL, TR, BR, BL],
                               "center": [x,y],
                               "homography": [[3] x3] (tag square [-1,1]^2 -> pixels),
                               "pose": {"R": [[3] x3], "t": [x,y,z], "reprojection_rms_px"}  (with --camera),
                               "pose_alternative": {same}  (when the planar ambiguity has a 2nd solution),
                               "timings_ms": {"blur","gradient","segmentation","line_fit","quads",
                                              "decode","pose","total"} (of the frame)}]}],
   "errors": [{"input": path, "error": message}]}
Pixel centres are at integer coordinates; camera frame x right, y down, z forward; tag frame origin at
the centre, x right, y down (as printed), z into the tag; X_cam = R X_tag + t (metres).

CSV output: a header row, then one row per detection:
  input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,tx,ty,tz,
  r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,min_decision_margin
(pose columns empty without --camera).
)";

// ------------------------------------------------------------------------------------------------
// Text helpers

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const std::set<std::string>& image_extensions() {
  static const std::set<std::string> e = {".png", ".jpg", ".jpeg", ".jpe", ".jp2", ".pgm", ".ppm", ".pbm",
                                          ".pnm", ".pam", ".pfm", ".tif", ".tiff", ".bmp", ".dib", ".webp",
                                          ".exr", ".hdr", ".pic", ".sr", ".ras"};
  return e;
}

const std::set<std::string>& video_extensions() {
  static const std::set<std::string> e = {".mp4", ".avi", ".mkv", ".mov", ".webm", ".m4v", ".mpg",
                                          ".mpeg", ".wmv", ".flv", ".ogv", ".3gp", ".ts", ".mjpeg", ".mjpg"};
  return e;
}

bool is_video_path(const fs::path& p) { return video_extensions().count(lower(p.extension().string())) > 0; }
bool is_image_path(const fs::path& p) { return image_extensions().count(lower(p.extension().string())) > 0; }

// One line for stderr: control characters (a newline in a file name or an OpenCV message) are shown
// escaped or as spaces, so every error stays on its own line.
std::string one_line(const std::string& s, bool escape) {
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7f) {
      out += ch;
    } else if (!escape) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// CSV: the same numbers, empty for non-finite; text fields quoted when they need it.
std::string csv_num(double v) { return std::isfinite(v) ? json_number(v) : std::string(); }

// ------------------------------------------------------------------------------------------------
// Options

struct Settings {
  DetectorOptions det;
  bool csv = false;
  std::optional<fs::path> draw;
  bool draw_is_file = false;
  std::optional<fs::path> debug_dir;
  int threads = 1;
};

std::vector<double> parse_list(const std::string& option, const std::string& text, std::size_t min_n,
                               std::size_t max_n, const std::string& what) {
  std::vector<double> v;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double x = 0;
    const auto r = std::from_chars(item.data(), item.data() + item.size(), x);
    if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size() || !std::isfinite(x))
      throw UsageError(option + " " + text + ": '" + item + "' is not a finite number (expected " + what + ")");
    v.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (v.size() < min_n || v.size() > max_n)
    throw UsageError(option + " " + text + ": expected " + what + ", got " + std::to_string(v.size()) +
                     (v.size() == 1 ? " number" : " numbers"));
  return v;
}

Settings parse_settings(const Args& a) {
  Settings s;
  if (a.has("family")) s.det.families = a.all("family");
  s.det.max_hamming = static_cast<int>(a.get_int("max-hamming", 1, 0, 16));
  if (const auto m = a.get("min-margin")) s.det.min_decision_margin = parse_double("--min-margin", *m, 0, 1);
  s.det.half_resolution = a.flag("half-res");

  std::optional<double> tag_size;
  if (const auto t = a.get("tag-size")) {
    const double v = parse_double("--tag-size", *t, -1e300, 1e300);
    if (!(v > 0)) throw UsageError("--tag-size " + *t + ": the tag size must be > 0 (metres)");
    tag_size = v;
  }
  if (const auto c = a.get("camera")) {
    const auto v = parse_list("--camera", *c, 4, 4, "fx,fy,cx,cy");
    if (!(v[0] > 0) || !(v[1] > 0))
      throw UsageError("--camera " + *c + ": focal lengths fx and fy must be > 0");
    if (v[2] < 0 || v[3] < 0) throw UsageError("--camera " + *c + ": principal point cx and cy must be >= 0");
    s.det.camera = CameraIntrinsics{v[0], v[1], v[2], v[3]};
  }
  if (const auto d = a.get("distortion")) {
    const auto v = parse_list("--distortion", *d, 4, 5, "k1,k2,p1,p2[,k3]");
    std::array<double, 5> k{0, 0, 0, 0, 0};
    std::copy(v.begin(), v.end(), k.begin());
    s.det.distortion = k;
  }
  if (s.det.camera && !tag_size) throw UsageError("--camera needs --tag-size (metres) for the pose");
  if (tag_size && !s.det.camera) throw UsageError("--tag-size needs --camera fx,fy,cx,cy");
  if (s.det.distortion && !s.det.camera) throw UsageError("--distortion needs --camera fx,fy,cx,cy");
  if (tag_size) s.det.tag_size = *tag_size;

  const std::string format = a.get_or("format", "json");
  if (format != "json" && format != "csv") throw UsageError("--format " + format + ": use json or csv");
  s.csv = format == "csv";
  s.threads = static_cast<int>(a.get_int("threads", hardware_threads(), 1, 1024));
  if (const auto d = a.get("debug-dir")) {
    if (d->empty()) throw UsageError("--debug-dir: empty path");
    s.debug_dir = fs::path(*d);
    std::error_code ec;
    if (fs::exists(*s.debug_dir, ec) && !fs::is_directory(*s.debug_dir, ec))
      throw UsageError("--debug-dir " + *d + ": exists and is not a directory");
  }
  if (const auto d = a.get("draw")) {
    if (d->empty()) throw UsageError("--draw: empty path");
    s.draw = fs::path(*d);
  }
  return s;
}

// ------------------------------------------------------------------------------------------------
// Inputs

// One unit of work: an image file, a decoded video frame, or an input already known to have failed.
struct Job {
  std::size_t index = 0;
  std::string label;      // as reported: the path, or "video#frameN"
  cv::Mat frame;          // the decoded image or video frame
  int frame_number = -1;  // >= 0 for video frames
  std::string out_name;   // base name of drawn/debug files
  std::string error;      // non-empty: this input failed before any work
};

struct Outcome {
  std::string label;
  int frame_number = -1;
  std::string error;  // empty = success
  int width = 0, height = 0;
  double detect_ms = 0;
  std::vector<Detection> detections;
};

// A source after expanding directories: an image, a video, or an error.
struct Source {
  fs::path path;
  std::string label;
  bool video = false;
  std::string error;
  std::string out_name;
};

std::string system_reason(const std::error_code& ec) { return ec ? ec.message() : std::string("unknown error"); }

std::vector<Source> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<Source> out;
  for (const std::string& in : inputs) {
    const fs::path p(in);
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    if (ec || !fs::exists(st)) {
      out.push_back({p, in, false, ec && ec != std::errc::no_such_file_or_directory ? system_reason(ec)
                                                                                  : "no such file or directory", {}});
      continue;
    }
    if (fs::is_directory(st)) {
      std::vector<fs::path> files;
      std::error_code it_ec;
      fs::recursive_directory_iterator it(p, fs::directory_options::skip_permission_denied, it_ec), end;
      for (; !it_ec && it != end; it.increment(it_ec)) {
        std::error_code fe;
        if (it->is_regular_file(fe) && is_image_path(it->path())) files.push_back(it->path());
      }
      if (it_ec) {
        out.push_back({p, in, false, "cannot read directory: " + system_reason(it_ec), {}});
        continue;
      }
      if (files.empty()) {
        out.push_back({p, in, false, "directory has no image files", {}});
        continue;
      }
      std::sort(files.begin(), files.end());
      for (const auto& f : files) out.push_back({f, f.string(), false, {}, {}});
      continue;
    }
    out.push_back({p, in, is_video_path(p), {}, {}});
  }
  // Unique output names: the file name without its extension, then _2, _3, ... on a clash.
  std::set<std::string> used;
  for (auto& s : out) {
    if (!s.error.empty()) continue;
    std::string stem = s.path.stem().string();
    if (stem.empty()) stem = "image";
    std::string name = stem;
    for (int k = 2; used.count(name); ++k) name = stem + "_" + std::to_string(k);
    used.insert(name);
    s.out_name = name;
  }
  return out;
}

// Image and video libraries print their own warnings and errors on stderr (libpng: "PNG input buffer
// is incomplete", libjpeg: "Premature end of JPEG file", ffmpeg: ...). They would break the
// one-line-per-error rule and repeat what our error line says, so decoding runs with stderr pointed
// at /dev/null. Only the main thread decodes and only the main thread prints, so nothing of ours is
// ever lost; the worker threads (detection, drawing) print nothing.
class QuietStderr {
 public:
  QuietStderr() {
    std::fflush(stderr);
    saved_ = ::dup(STDERR_FILENO);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ < 0 || null < 0 || ::dup2(null, STDERR_FILENO) < 0) {
      if (saved_ >= 0) ::close(saved_);
      saved_ = -1;
    }
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

// ------------------------------------------------------------------------------------------------
// Processing one input

class Processor {
 public:
  Processor(const Settings& s, const Detector& det) : s_(s), det_(det) {}

  // `ws`: the calling worker's own buffers, so a stream of frames of one size allocates them once.
  Outcome run(Job& job, DetectorWorkspace& ws) const {
    Outcome o;
    o.label = job.label;
    o.frame_number = job.frame_number;
    if (!job.error.empty()) {
      o.error = job.error;
      return o;
    }
    std::vector<fs::path> written;
    try {
      const cv::Mat img = std::move(job.frame);
      o.width = img.cols;
      o.height = img.rows;
      const bool debug = s_.debug_dir.has_value();
      DetectorTrace trace;
      const auto t0 = std::chrono::steady_clock::now();
      o.detections = detect(det_, img, ws, debug ? &trace : nullptr);
      o.detect_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

      // Pictures: everything encoded first, then written (each atomically); on a failure the
      // pictures already written for this input are removed, so a failed input leaves nothing.
      std::vector<std::pair<fs::path, std::string>> files;
      if (s_.draw) {
        const cv::Mat pic = draw_detections(img, o.detections, det_.options(), det_.families().size() > 1);
        if (s_.draw_is_file) {
          files.emplace_back(*s_.draw, encode(pic, lower(s_.draw->extension().string())));
        } else {
          files.emplace_back(*s_.draw / (job.out_name + ".png"), encode(pic, ".png"));
        }
      }
      if (debug) {
        const auto pics = stage_pictures(to_float_image(img), trace, o.detections, det_);
        for (std::size_t i = 0; i < pics.size(); ++i)
          files.emplace_back(*s_.debug_dir / (job.out_name + "_" + kStages[i] + ".png"), encode(pics[i], ".png"));
      }
      for (const auto& [path, bytes] : files) {
        make_parent(path);
        write_file_atomic(path, bytes);
        written.push_back(path);
      }
    } catch (const std::exception& e) {
      fail(o, written, e.what());
    } catch (...) {
      fail(o, written, "unknown error");
    }
    return o;
  }

  // After the run: the directories it created that hold nothing (their inputs failed, e.g. on a full
  // disk) are removed, deepest first. Not done in fail(): another worker may be about to write there.
  void remove_empty_created_dirs() const {
    std::lock_guard<std::mutex> lock(dir_mutex_);
    std::vector<fs::path> dirs = created_dirs_;
    std::sort(dirs.begin(), dirs.end(), [](const fs::path& a, const fs::path& b) {
      return std::distance(a.begin(), a.end()) > std::distance(b.begin(), b.end());
    });
    for (const auto& d : dirs) {
      std::error_code ec;
      fs::remove(d, ec);  // fails, harmlessly, on a directory with files in it
    }
  }

 private:
  static void fail(Outcome& o, const std::vector<fs::path>& written, const std::string& why) {
    for (const auto& p : written) {
      std::error_code ec;
      fs::remove(p, ec);
    }
    o.error = why.empty() ? "failed" : why;
    o.detections.clear();
  }

  // Output directories are created on first use (so a run whose inputs all fail creates nothing).
  void make_parent(const fs::path& file) const {
    if (s_.draw_is_file && s_.draw && file == *s_.draw) return;
    const fs::path dir = file.parent_path();
    std::lock_guard<std::mutex> lock(dir_mutex_);
    std::error_code ec;
    if (fs::is_directory(dir, ec)) return;
    for (fs::path d = dir; !d.empty() && !fs::exists(d, ec); d = d.parent_path()) {
      created_dirs_.push_back(d);
      if (d == d.parent_path()) break;
    }
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
  }

  const Settings& s_;
  const Detector& det_;
  mutable std::mutex dir_mutex_;
  mutable std::vector<fs::path> created_dirs_;  // by make_parent, for remove_empty_created_dirs
};

// ------------------------------------------------------------------------------------------------
// Output

class Sink {
 public:
  Sink(const Settings& s, const Detector& det) : s_(s), det_(det), tty_(::isatty(STDERR_FILENO) != 0) {}

  void begin() {
    if (s_.csv) {
      put("input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,tx,ty,tz,"
          "r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,min_decision_margin\n");
      return;
    }
    const DetectorOptions& o = det_.options();
    std::string h = "{\n  \"tool\": \"tagbench detect\",\n  \"options\": {\"families\": [";
    for (std::size_t i = 0; i < det_.families().size(); ++i)
      h += (i ? ", " : "") + json_string(det_.families()[i].name());
    h += "], \"max_hamming\": " + std::to_string(o.max_hamming) +
         ", \"min_decision_margin\": " + json_number(o.min_decision_margin) +
         ", \"half_res\": " + (o.half_resolution ? "true" : "false") + ", \"camera\": ";
    if (o.camera)
      h += "[" + json_number(o.camera->fx) + ", " + json_number(o.camera->fy) + ", " + json_number(o.camera->cx) +
           ", " + json_number(o.camera->cy) + "]";
    else
      h += "null";
    h += ", \"distortion\": ";
    if (o.distortion) {
      h += "[";
      for (std::size_t i = 0; i < 5; ++i) h += (i ? ", " : "") + json_number((*o.distortion)[i]);
      h += "]";
    } else {
      h += "null";
    }
    h += ", \"tag_size\": " + (o.camera ? json_number(o.tag_size) : std::string("null")) + "},\n  \"images\": [";
    put(h);
  }

  void emit(const Outcome& o) {
    if (!o.error.empty()) {
      errors_.push_back(o);
      std::fprintf(stderr, "%stagbench detect: %s: %s\n", tty_ ? "\r\033[K" : "", one_line(o.label, true).c_str(),
                   one_line(o.error, false).c_str());
      std::fflush(stderr);
      return;
    }
    if (s_.csv) emit_csv(o);
    else emit_json(o);
  }

  void end() {
    if (!s_.csv) {
      std::string t = images_ ? "\n  ],\n  \"errors\": [" : "],\n  \"errors\": [";
      for (std::size_t i = 0; i < errors_.size(); ++i)
        t += std::string(i ? "," : "") + "\n    {\"input\": " + json_string(errors_[i].label) +
             ", \"error\": " + json_string(errors_[i].error) + "}";
      t += errors_.empty() ? "]\n}\n" : "\n  ]\n}\n";
      put(t);
    }
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) throw std::runtime_error("cannot write the output to stdout");
  }

  std::size_t failures() const { return errors_.size(); }

 private:
  void put(const std::string& s) { std::fwrite(s.data(), 1, s.size(), stdout); }

  static std::string point(const Eigen::Vector2d& p) {
    return "[" + json_number(p.x()) + ", " + json_number(p.y()) + "]";
  }
  static std::string matrix(const Eigen::Matrix3d& m) {
    std::string s = "[";
    for (int i = 0; i < 3; ++i)
      s += std::string(i ? ", " : "") + "[" + json_number(m(i, 0)) + ", " + json_number(m(i, 1)) + ", " +
           json_number(m(i, 2)) + "]";
    return s + "]";
  }
  static std::string pose(const PoseSolution& p) {
    return "{\"R\": " + matrix(p.pose.R) + ", \"t\": [" + json_number(p.pose.t.x()) + ", " + json_number(p.pose.t.y()) +
           ", " + json_number(p.pose.t.z()) + "], \"reprojection_rms_px\": " + json_number(p.reprojection_rms_px) + "}";
  }

  void emit_json(const Outcome& o) {
    std::string s = images_++ ? ",\n    {" : "\n    {";
    s += "\"input\": " + json_string(o.label);
    if (o.frame_number >= 0) s += ", \"frame\": " + std::to_string(o.frame_number);
    s += ", \"width\": " + std::to_string(o.width) + ", \"height\": " + std::to_string(o.height) +
         ", \"detect_ms\": " + json_number(o.detect_ms) + ", \"detections\": [";
    for (std::size_t i = 0; i < o.detections.size(); ++i) {
      const Detection& d = o.detections[i];
      s += i ? ",\n      {" : "\n      {";
      s += "\"family\": " + json_string(d.family) + ", \"id\": " + std::to_string(d.id) +
           ", \"hamming\": " + std::to_string(d.hamming) + ", \"rotation\": " + std::to_string(d.rotation) +
           ", \"decision_margin\": " + json_number(d.decision_margin) + ",\n       \"corners\": [";
      for (std::size_t k = 0; k < 4; ++k) s += (k ? ", " : "") + point(d.corners[k]);
      s += "], \"center\": " + point(d.center) + ",\n       \"homography\": " + matrix(d.homography);
      if (d.pose) s += ",\n       \"pose\": " + pose(*d.pose);
      if (d.pose_alternative) s += ",\n       \"pose_alternative\": " + pose(*d.pose_alternative);
      const StageTimings& t = d.timings;
      s += ",\n       \"timings_ms\": {\"blur\": " + json_number(t.blur) +
           ", \"gradient\": " + json_number(t.gradient) + ", \"segmentation\": " + json_number(t.segmentation) +
           ", \"line_fit\": " + json_number(t.line_fit) + ", \"quads\": " + json_number(t.quads) +
           ", \"decode\": " + json_number(t.decode) + ", \"pose\": " + json_number(t.pose) +
           ", \"total\": " + json_number(t.total) + "}}";
    }
    s += o.detections.empty() ? "]}" : "\n    ]}";
    put(s);
  }

  void emit_csv(const Outcome& o) {
    for (const Detection& d : o.detections) {
      std::vector<std::string> f = {csv_field(o.label), csv_field(d.family), std::to_string(d.id),
                                    std::to_string(d.hamming), std::to_string(d.rotation), csv_num(d.decision_margin)};
      for (const auto& c : d.corners) {
        f.push_back(csv_num(c.x()));
        f.push_back(csv_num(c.y()));
      }
      f.push_back(csv_num(d.center.x()));
      f.push_back(csv_num(d.center.y()));
      if (d.pose) {
        const Pose& p = d.pose->pose;
        for (int i = 0; i < 3; ++i) f.push_back(csv_num(p.t(i)));
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) f.push_back(csv_num(p.R(i, j)));
        f.push_back(csv_num(d.pose->reprojection_rms_px));
      } else {
        f.resize(f.size() + 13);
      }
      f.push_back(std::to_string(det_.options().max_hamming));
      f.push_back(det_.options().half_resolution ? "1" : "0");
      f.push_back(csv_num(det_.options().min_decision_margin));
      std::string line;
      for (std::size_t i = 0; i < f.size(); ++i) {
        if (i) line += ',';
        line += f[i];
      }
      line += '\n';
      put(line);
    }
  }

  const Settings& s_;
  const Detector& det_;
  bool tty_;
  std::size_t images_ = 0;
  std::vector<Outcome> errors_;
};

// ------------------------------------------------------------------------------------------------
// The ordered parallel pipeline: the main thread reads inputs (and video frames) into jobs, workers
// detect, the main thread prints outcomes in input order. At most `window` jobs are in flight.

class Pipeline {
 public:
  Pipeline(const Processor& proc, Sink& sink, int threads)
      : proc_(proc), sink_(sink), window_(static_cast<std::size_t>(threads) * 2 + 2),
        bar_("detect", ::isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()) {
    for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
  }
  ~Pipeline() { stop(); }

  void add_expected(std::size_t n) { expected_ += n; }

  void submit(Job job) {
    while (submitted_ - emitted_ >= window_) emit_next();
    job.index = submitted_++;
    {
      std::lock_guard<std::mutex> lock(m_);
      queue_.push_back(std::move(job));
    }
    work_cv_.notify_one();
  }

  void finish() {
    while (emitted_ < submitted_) emit_next();
    stop();
  }

 private:
  void emit_next() {
    Outcome o;
    {
      std::unique_lock<std::mutex> lock(m_);
      done_cv_.wait(lock, [&] { return done_.count(emitted_) > 0; });
      auto it = done_.find(emitted_);
      o = std::move(it->second);
      done_.erase(it);
    }
    sink_.emit(o);
    ++emitted_;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const std::size_t total = std::max(expected_, emitted_);
    const double rate = elapsed > 0 ? static_cast<double>(emitted_) / elapsed : 0.0;
    char detail[64];
    std::snprintf(detail, sizeof detail, "%.1f img/s", rate);
    bar_.update(static_cast<double>(emitted_) / static_cast<double>(total),
                std::to_string(emitted_) + "/" + std::to_string(total) + " images", detail,
                rate > 0 ? static_cast<double>(total - emitted_) / rate : -1.0);
  }

  void work() {
    DetectorWorkspace ws;  // this worker's detection buffers, reused frame after frame
    while (true) {
      Job job;
      {
        std::unique_lock<std::mutex> lock(m_);
        work_cv_.wait(lock, [&] { return closing_ || !queue_.empty(); });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      const std::size_t index = job.index;
      Outcome o = proc_.run(job, ws);
      {
        std::lock_guard<std::mutex> lock(m_);
        done_.emplace(index, std::move(o));
      }
      done_cv_.notify_all();
    }
  }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(m_);
      closing_ = true;
    }
    work_cv_.notify_all();
    for (auto& t : workers_)
      if (t.joinable()) t.join();
  }

  const Processor& proc_;
  Sink& sink_;
  std::size_t window_;
  ProgressBar bar_;
  std::chrono::steady_clock::time_point start_;
  std::size_t submitted_ = 0, emitted_ = 0, expected_ = 0;
  std::mutex m_;
  std::condition_variable work_cv_, done_cv_;
  std::deque<Job> queue_;
  std::map<std::size_t, Outcome> done_;
  bool closing_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace

int cmd_detect(const Words& words) {
  if (wants_help(words, kHelp)) return 0;
  const Args a(words, {{"family", true, true},
                       {"max-hamming"},
                       {"min-margin"},
                       {"camera"},
                       {"distortion"},
                       {"tag-size"},
                       {"half-res", false},
                       {"format"},
                       {"draw"},
                       {"debug-dir"},
                       {"threads"}});
  if (a.positionals().empty()) throw UsageError("no input given (images, directories or videos)");
  Settings s = parse_settings(a);

  // --draw: a picture file for a single image input, a directory otherwise.
  if (s.draw) {
    std::error_code ec;
    const fs::path in(a.positionals()[0]);
    const bool single_image = a.positionals().size() == 1 && !fs::is_directory(in, ec) && !is_video_path(in);
    s.draw_is_file = single_image && !fs::is_directory(*s.draw, ec);
    if (s.draw_is_file) {
      const std::string ext = lower(s.draw->extension().string());
      if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
        throw UsageError("--draw " + s.draw->string() + ": for one image, OUT is a picture: use .png or .jpg");
    } else if (fs::exists(*s.draw, ec) && !fs::is_directory(*s.draw, ec)) {
      throw UsageError("--draw " + s.draw->string() + ": with several inputs OUT must be a directory");
    }
  }

  const Detector detector(s.det);  // throws on a family that cannot be loaded
  // OpenCV's own warnings (decoders, video back ends) would break the one-line-per-error rule.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  cv::setNumThreads(1);  // parallelism is across images; OpenCV's own threads would oversubscribe

  const std::vector<Source> sources = expand_inputs(a.positionals());
  const Processor proc(s, detector);
  Sink sink(s, detector);
  sink.begin();
  {
    Pipeline pipe(proc, sink, s.threads);
    for (const Source& src : sources)
      if (!src.video) pipe.add_expected(1);
    for (const Source& src : sources) {
      Job job;
      job.label = src.label;
      job.out_name = src.out_name;
      if (!src.error.empty()) {
        job.error = src.error;
        pipe.submit(std::move(job));
        continue;
      }
      if (!src.video) {
        try {
          const QuietStderr quiet;
          job.frame = load_image(src.path);
        } catch (const std::exception& e) {
          job.error = e.what();
        }
        pipe.submit(std::move(job));
        continue;
      }
      cv::VideoCapture cap;
      try {
        const QuietStderr quiet;
        cap.open(src.path.string());
      } catch (const cv::Exception&) {
      }
      if (!cap.isOpened()) {
        job.error = "cannot open the video (corrupt or unsupported format)";
        pipe.submit(std::move(job));
        continue;
      }
      const double count = cap.get(cv::CAP_PROP_FRAME_COUNT);
      if (count > 0 && count < 1e9) pipe.add_expected(static_cast<std::size_t>(count));
      int n = 0;
      while (true) {
        cv::Mat frame;
        bool ok = false;
        try {
          const QuietStderr quiet;
          ok = cap.read(frame);
        } catch (const cv::Exception&) {
          ok = false;
        }
        if (!ok || frame.empty()) break;
        Job fj;
        fj.label = src.label + "#frame" + std::to_string(n);
        fj.frame_number = n;
        fj.out_name = src.out_name + "_frame" + std::to_string(n);
        fj.frame = std::move(frame);
        pipe.submit(std::move(fj));
        ++n;
      }
      if (n == 0) {
        job.error = "no frame could be read from the video";
        pipe.submit(std::move(job));
      }
    }
    pipe.finish();
  }
  proc.remove_empty_created_dirs();
  sink.end();
  return sink.failures() > 0 ? 1 : 0;
}

}  // namespace tagbench::cli
