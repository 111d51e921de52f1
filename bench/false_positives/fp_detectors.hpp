#pragma once
// False detections of whole detectors on the natural-image corpus, as users run them (issue 5):
// every detector at its defaults, one family at a time, on every image. The corpus holds no tags,
// so every detection is false. Reported per image and per megapixel (a Poisson rate with its exact
// 95 % interval, since one image can hold several), as the share of images with at least one
// (Wilson interval), for all images, stills and video frames apart, and per group.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "candidates.hpp"
#include "external/external_detector.hpp"
#include "raytrace/comparators.hpp"
#include "stats.hpp"

namespace tagbench::bench {

struct FpDetectorsOptions {
  // tagbench: our default profile (bits corrected by family); tagbench-thorough: the thorough profile
  // (full-resolution line quads, coarse pass); tagbench-paper: the paper's detector (1 bit corrected);
  // libapriltag-d2: libapriltag 3.3's defaults (quad_decimate 2, 2 bits corrected); aruco-default:
  // OpenCV 4.6 aruco's defaults.
  std::vector<std::string> detectors = {"tagbench", "tagbench-thorough", "tagbench-paper", "libapriltag-d2",
                                        "aruco-default"};
  std::vector<std::string> families = {"16h5", "25h9", "36h11"};
  // Detectors outside the build, named in `detectors`: each runs once on every readable image (its
  // path), all families at once; its detections count under the family each names (others dropped),
  // its time ("ms" of its lines) under each family.
  std::vector<ExternalDetector> external;
  int jobs = 0;  // images at once; 0: all cores. The results do not depend on it.
};

struct FalseDetection {
  std::uint32_t image = 0;  // index into FpDetectorsRun::images
  std::string detector, family;
  int id = -1, hamming = -1;  // -1: the detector does not say
  double decision_margin = 0; // Found::decision_margin (NaN: the detector does not say)
  Corners corners;            // printed TL, TR, BR, BL, pixel centres at integers
};

struct FpDetectorsRun {
  std::vector<corpus::CandidateImage> images;  // width/height/status filled in by the run
  std::vector<FalseDetection> detections;      // by image, then detector, then family (options' order)
  // Per detector and family (options' order, detector-major): wall time summed over the images, ms.
  std::vector<double> ms;
  FpDetectorsOptions options;
};

struct FpDetectorsProgress {
  std::size_t images_done = 0, images_total = 0, detections = 0;
};

// Reads every image (8-bit grey) and runs every detector x family on it; unreadable images are kept
// with status "unreadable" and their reason, and count nowhere. Throws std::invalid_argument for an
// unknown detector or a family a detector does not know.
FpDetectorsRun run_fp_detectors(const std::filesystem::path& dir, std::vector<corpus::CandidateImage> images,
                                const FpDetectorsOptions& options,
                                const std::function<void(const FpDetectorsProgress&)>& progress = {});

struct FpDetectorRow {
  std::string detector, family;
  std::string subset;  // "all", "still", "video-frame" or "group:NAME"
  std::uint64_t images = 0;
  double megapixels = 0;
  std::uint64_t detections = 0, images_with_detections = 0;
  double per_image = 0, per_megapixel = 0, image_share = 0;
  Interval per_image_ci, per_megapixel_ci, image_share_ci;
  double ms_per_image = 0, megapixels_per_second = 0;  // "all" rows only (0 elsewhere)
};

// The rows: for each detector and family, "all", "still", "video-frame", then each group (sorted).
std::vector<FpDetectorRow> fp_detector_rows(const FpDetectorsRun& run);

std::string fp_detectors_csv(const std::vector<FpDetectorRow>& rows);
// One row per false detection: image file, group, kind, detector, family, id, hamming, corners,
// decision_margin (empty when the detector does not report one).
std::string fp_detections_csv(const FpDetectorsRun& run);

}  // namespace tagbench::bench
