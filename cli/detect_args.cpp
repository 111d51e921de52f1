#include "cli/detect_args.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/format.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

const char* const kHelp = R"(usage: tagbench detect IMAGE_OR_DIR_OR_VIDEO... [--family F]... [--max-hamming K]
                       [--min-margin M] [--camera fx,fy,cx,cy] [--distortion k1,k2,p1,p2,k3] [--tag-size M] [--half-res]
                       [--profile default|thorough|paper] [--format json|jsonl|csv] [--draw OUT] [--debug-dir DIR]
                       [--input-gamma G] [--threads T] [--explain X,Y[,FAMILY:ID]]...

Detects tags in every input and prints the detections on stdout, in input order.
Inputs: image files (png, jpg, pgm, tiff, ...; colour and 16-bit are converted to gray), directories
(searched recursively, image extensions only, sorted), videos (.mp4 .avi .mkv .mov .webm .m4v .mpg
.mpeg .wmv .flv .ogv .3gp .ts: every frame, reported as FILE#frameN with N from 0); a lone '-': the
paths are read from stdin, one a line (how the experiments run an external detector).
  --profile P          default (the default profile: threshold quads, refined edges, cells read over
                       their area), thorough (the default with its quads from straight edges found on
                       the full-resolution image, even with --half-res, and a coarse pass: more of
                       the small, faint tags of photographs for about twice the time) or paper (the 2011 paper's
                       detector exactly, sections III-IV)
  --family F           tag family, a built-in name or a family file; repeatable (default 36h11)
  --max-hamming K      payload bits corrected at most, for every family: 0..16 and below the smallest
                       minimum Hamming distance of the families (default: the paper
                       profile 1; the default profile by family, min(3, (h - 1) / 3) for a family of
                       minimum distance h: 36h11 3, 25h9 2, 16h5 1)
  --min-margin M       drop detections whose decision_margin is below M, 0..1 (default 0: keep all,
                       as the paper). Beyond the paper: against false detections of small families;
                       see results/margin_tradeoff.csv for what each M costs and saves
  --camera fx,fy,cx,cy intrinsics in pixels (fx, fy > 0; cx, cy >= 0); needs --tag-size; adds poses
  --distortion k1,k2,p1,p2[,k3]
                       OpenCV lens distortion; needs --camera (corners are undistorted for the pose)
  --tag-size M         edge of the black square in metres (> 0); needs --camera
  --half-res           find quads at half resolution (the paper's faster option)
  --input-gamma G      the images' encoding gamma, 0.1..10 (value = linear^(1/G); default 1: the image
                       as it is, right for linear cameras, raw data and renders); 2.2 for camera JPEGs
                       and PNGs (sRGB-like): corners about 5 % nearer the truth. A wrong value costs
                       more (a linear camera's frames read as 2.2: corner error about 2 x). The default
                       profile locates a found tag's sides on linear intensities; which tags are
                       decoded does not depend on it (--profile paper ignores it)
  --format json|jsonl|csv
                       output format (default json; jsonl: a line per image, below)
  --draw OUT           draw the detections like the paper's Fig. 1 (outline, printed top-left corner
                       as a dot, id at the centre, pose axes x red, y green, z blue, tag size / 2 long;
                       z points into the tag). One image input: OUT is the picture (.png, .jpg);
                       otherwise OUT is a directory and each image goes to OUT/<name>.png
                       (<name> = file name without extension, made unique with _2, _3, ...;
                       video frames: <name>_frameN.png)
  --debug-dir DIR      the stages of the paper's Figs. 3 and 4 as DIR/<name>_<stage>.png, stages
                       gradient_magnitude, gradient_direction, clusters (at the segmentation's
                       resolution: half size with --half-res), segments (notch toward the light side)
                       (these four with --profile paper only: the default profile has no gradients),
                       threshold (the default profile's pixel classes: dark black, light white, too
                       little contrast grey) and boundaries (each boundary group's dark side in its
                       colour; grey: too small to fit) (these two at the threshold's resolution, without
                       --profile paper: where a tag has no quad they show its square joined to a dark
                       neighbour, its ring broken or its outline split among groups),
                       quads (every candidate; dot on its first corner), samples (the detected tags'
                       sample points: white ring white, black ring black, payload yellow)
  --threads T          images processed in parallel (default: all cores); output order is input order
  --explain X,Y[,FAMILY:ID]
                       why no tag was reported at pixel (X, Y) of each image (repeatable): the stage
                       where it was lost, from the detection's trace. A detection whose quad holds the
                       point: "detected". Else the candidate quad holding it that got furthest:
                       quad_rejected (border pre-filter, degenerate corners, cells not readable),
                       misread (read, not decoded within the bits corrected), below_margin,
                       withdrawn (decoded, then withdrawn by the occlusion refit), duplicate; with
                       FAMILY:ID (the tag you expect there) also wrong_id and the bits of its code read
                       wrong. No quad holds it: no_quad (the default profile's threshold quad finder,
                       with its pixel classes and the boundary groups within 10 px: a group far wider
                       than the tag, the square joined to its surroundings; none, square and ring not
                       classed apart; --profile paper: segments within 50 px), no_segment (gradient
                       clusters within 50 px), no_cluster; outside_image for a point off the image. A
                       FAMILY not searched (--family) is a usage error. JSON and JSON lines: an
                       "explain" list in each image (below);
                       CSV: one line per point on stderr, "tagbench detect: INPUT: explain X,Y: STAGE: text"

Errors: an input that cannot be read (missing, unreadable, 0 bytes, corrupt) prints one line on stderr
naming it, the other inputs are still processed, and the exit status is 1 (so does a video frame that
cannot be decoded before the video's declared end). Bad options, a family that cannot be loaded
included, exit with 2. A 1-pixel image is valid and has no detections. Files are written atomically;
nothing is written for a failed input. SIGINT or SIGTERM: the images begun are finished and printed,
an error for the input named (interrupted) is added, the output is closed whole; exit status 130 or
143.

JSON output (one document for the whole run):
  {"tool": "tagbench detect",
   "options": {"families": [names], "profile": "default", "thorough" or "paper", "max_hamming": K, "min_decision_margin": M, "half_res": bool,
               "input_gamma": G,
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
                               each with "pattern_correlation" when the pose choice judged the two;
                               "pose_ambiguous": true  (the image could not tell them apart),
                               "timings_ms": {"blur","gradient","segmentation","line_fit","quads",
                                              "decode","pose","total"} (of the frame)}],
               "explain": [{"at": [x,y], "given": "X,Y[,FAMILY:ID]", "stage", "bits_wrong": n or null,
                            "quad": index or null, "text"}]  (with --explain only)}],
   "errors": [{"input": path, "error": message}]}
Pixel centres are at integer coordinates; camera frame x right, y down, z forward; tag frame origin at
the centre, x right, y down (as printed), z into the tag; X_cam = R X_tag + t (metres).

JSON lines (--format jsonl; what `tagbench score` and the experiments' external detectors read): one
line per input image, in input order:
  {"image": path or "video#frameN", "width": W, "height": H, "ms": wall time,
   "detections": [{"family", "id", "hamming", "decision_margin", "corners": [[x,y] x4: printed TL, TR,
                   BR, BL], "pose": {"R": [[3] x3], "t": [x,y,z]} (with --camera)}],
   "explain": [...] (with --explain, as in the JSON document)}
and for an input that cannot be read {"image": path, "error": message} (also on stderr; exit status 1).

CSV output: a header row, then one row per detection:
  input,family,id,hamming,rotation,decision_margin,x0,y0,x1,y1,x2,y2,x3,y3,cx,cy,tx,ty,tz,
  r00,r01,r02,r10,r11,r12,r20,r21,r22,reprojection_rms_px,max_hamming,half_res,min_decision_margin,
  input_gamma
(pose columns empty without --camera).
)";

namespace {

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

}  // namespace

Settings parse_settings(const Args& a) {
  Settings s;
  s.profile = a.get_or("profile", "default");
  if (const auto p = DetectorOptions::named_profile(s.profile))
    s.det = *p;
  else
    throw UsageError("--profile " + s.profile + ": expected default, thorough or paper");
  if (a.has("family")) {  // each once: `--family 36h11 --family 36h11` is one family, not two of one name
    s.det.families.clear();
    for (const auto& f : a.all("family"))
      if (std::find(s.det.families.begin(), s.det.families.end(), f) == s.det.families.end()) s.det.families.push_back(f);
  }
  if (a.has("max-hamming")) {  // the same bits for every family, as asked
    s.det.max_hamming = static_cast<int>(a.get_int("max-hamming", 1, 0, 16));
    s.det.hamming_by_family = false;
  }
  if (const auto m = a.get("min-margin")) s.det.min_decision_margin = parse_double("--min-margin", *m, 0, 1);
  s.det.half_resolution = a.flag("half-res");
  if (const auto g = a.get("input-gamma")) s.det.input_gamma = parse_double("--input-gamma", *g, 0.1, 10);

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
  if (format != "json" && format != "csv" && format != "jsonl")
    throw UsageError("--format " + format + ": use json, jsonl or csv");
  s.csv = format == "csv";
  s.jsonl = format == "jsonl";
  s.threads = static_cast<int>(a.get_int("threads", hardware_threads(), 1, 1024));
  if (const auto d = a.get("debug-dir")) {
    if (d->empty()) throw UsageError("--debug-dir: empty path");
    s.debug_dir = fs::path(*d);
    std::error_code ec;
    if (fs::exists(*s.debug_dir, ec) && !fs::is_directory(*s.debug_dir, ec))
      throw UsageError("--debug-dir " + *d + ": exists and is not a directory");
  }
  for (const auto& e : a.all("explain")) s.explain.push_back(parse_explain_point(e));
  if (const auto d = a.get("draw")) {
    if (d->empty()) throw UsageError("--draw: empty path");
    s.draw = fs::path(*d);
  }
  return s;
}

}  // namespace tagbench::cli::detect_cmd
