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
//       "input_gamma": 1,                     // the images' encoding gamma (--input-gamma)
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
//   min_decision_margin,input_gamma
// (pose columns empty without --camera; fields quoted as RFC 4180 when needed).
//
// Decisions: a 1-pixel (or any tiny) image is valid input and has no detections; a missing,
// unreadable, 0-byte or undecodable file, a directory without images and a video without a
// readable frame are errors of that input: one line on stderr, an entry in "errors", the other
// inputs still processed, exit status 1. Bad options are usage errors (exit 2) reported before
// anything is read or written; so is a family that cannot be loaded. SIGINT or SIGTERM stop the run
// between images: the images begun are finished and printed, then an "errors" entry "interrupted"
// and a complete document (JSON closed, CSV rows whole), exit status 130 or 143.
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/detect_args.hpp"
#include "cli/detect_inputs.hpp"
#include "cli/detect_output.hpp"
#include "cli/detect_pipeline.hpp"
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

using namespace detect_cmd;

// The signal that asked the run to stop (SIGINT, SIGTERM), 0 while none has.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

// Installs on_stop_signal for SIGINT and SIGTERM while it lives, then restores what was there.
class StopSignals {
 public:
  StopSignals() : int_(std::signal(SIGINT, on_stop_signal)), term_(std::signal(SIGTERM, on_stop_signal)) {}
  ~StopSignals() {
    std::signal(SIGINT, int_);
    std::signal(SIGTERM, term_);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*int_)(int);
  void (*term_)(int);
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
                       {"input-gamma"},
                       {"profile"},
                       {"format"},
                       {"draw"},
                       {"debug-dir"},
                       {"threads"},
                       {"explain", true, true}});
  if (a.positionals().empty()) throw UsageError("no input given (images, directories or videos)");
  Settings s = parse_settings(a);
  std::vector<std::string> inputs = a.positionals();
  if (inputs.size() > 1 && std::find(inputs.begin(), inputs.end(), "-") != inputs.end())
    throw UsageError("-: the paths from stdin are the only input when given (no other inputs beside '-')");
  if (inputs.size() == 1 && inputs[0] == "-") {  // the paths on stdin, one a line (as the experiments' external detectors get them)
    inputs.clear();
    for (std::string l; std::getline(std::cin, l);) {
      if (!l.empty() && l.back() == '\r') l.pop_back();  // a list written on Windows
      if (!l.empty()) inputs.push_back(l);
    }
    if (inputs.empty()) throw UsageError("-: no input paths on stdin");
  }

  // --draw: a picture file for a single image input, a directory otherwise.
  if (s.draw) {
    std::error_code ec;
    const fs::path in(inputs[0]);
    const bool single_image = inputs.size() == 1 && !fs::is_directory(in, ec) && !is_video_path(in);
    s.draw_is_file = single_image && !fs::is_directory(*s.draw, ec);
    if (s.draw_is_file) {
      const std::string ext = lower(s.draw->extension().string());
      if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
        throw UsageError("--draw " + s.draw->string() + ": for one image, OUT is a picture: use .png or .jpg");
    } else if (fs::exists(*s.draw, ec) && !fs::is_directory(*s.draw, ec)) {
      throw UsageError("--draw " + s.draw->string() + ": with several inputs OUT must be a directory");
    }
  }

  // A family that cannot be loaded, or options the families do not admit (two of one name,
  // --max-hamming at or above a family's distance), is a bad option: exit 2.
  const Detector detector = usage_on_invalid("", [&] {
    try {
      return Detector(s.det);
    } catch (const std::invalid_argument& e) {
      // The library names its fields (DetectorOptions::validate); the user gave flags.
      const std::string what = e.what();
      for (const auto& [field, flag] : {std::pair{"max_hamming", "--max-hamming"}, std::pair{"tag_size", "--tag-size"},
                                        std::pair{"camera.", "--camera "}, std::pair{"distortion.", "--distortion "}})
        if (what.starts_with(field)) throw std::invalid_argument(flag + what.substr(std::string_view(field).size()));
      throw;
    }
  });
  // A tag of a family not searched could only ever be "wrong_id": say so now, against the families
  // the detector loaded.
  for (const ExplainPoint& p : s.explain)
    if (p.family && std::none_of(detector.families().begin(), detector.families().end(),
                                 [&](const TagFamily& f) { return f.name() == p.family->name(); }))
      throw UsageError("--explain " + p.spec + ": family " + p.family->name() + " is not searched (add --family " +
                       p.family->name() + ")");
  cv::setNumThreads(1);  // parallelism is across images; OpenCV's own threads would oversubscribe

  const std::vector<Source> sources = expand_inputs(inputs);
  const Processor proc(s, detector);
  Sink sink(s, detector);
  g_stop_signal = 0;
  const StopSignals stop_signals;  // before the document begins: from here on it is always closed
  sink.begin();
  {
    Pipeline pipe(proc, sink, s.threads);
    for (const Source& src : sources)
      if (!src.video) pipe.add_expected(1);
    for (const Source& src : sources) {
      if (g_stop_signal) break;
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
      while (!g_stop_signal) {
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
      if (g_stop_signal) break;
      if (n == 0) {
        job.error = "no frame could be read from the video";
        pipe.submit(std::move(job));
      } else if (count > 0 && count < 1e9 && n + 1 < static_cast<long long>(count)) {
        // The container declares more frames than could be decoded: a corrupt frame ends the reading
        // (the frames after it are lost), which must not pass for the end of the video. One frame
        // short is tolerated: some containers' counts are estimated from the duration.
        job.label = src.label + "#frame" + std::to_string(n);
        job.error = "cannot decode frame " + std::to_string(n) + " of the " + std::to_string(static_cast<long long>(count)) +
                    " the video declares (corrupt or truncated); the frames after it are not read";
        pipe.submit(std::move(job));
      }
    }
    if (const int sig = g_stop_signal) {
      Job stopped;
      stopped.label = "(interrupted)";
      stopped.error = std::string(sig == SIGINT ? "SIGINT" : "SIGTERM") +
                      ": stopped; the images begun were finished, the rest not read";
      pipe.submit(std::move(stopped));
    }
    pipe.finish();
  }
  proc.remove_empty_created_dirs();
  sink.end();
  if (const int sig = g_stop_signal) return 128 + sig;
  return sink.failures() > 0 ? 1 : 0;
}

}  // namespace tagbench::cli
