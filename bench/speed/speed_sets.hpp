#pragma once
// Detector speed on whole image sets (issue 17, section 5): the natural-image corpus, the ray-traced
// frames of the sweeps, the realistic set and the synthetic scenes, each reported apart.
//
// How it is measured, so that a ratio means what it says:
// - every detector single-threaded (the caller sets cv::setNumThreads(1)), one object per detector
//   kept for the whole run, so our detector reuses one warm DetectorWorkspace (a Comparator keeps it);
// - every detector in this one process on the same 8-bit gray image, image after image, the order of
//   the detectors rotated from one image to the next, so a drift in the machine's speed hits all alike;
// - `repeats` timed runs per image and detector, the fastest kept (the least disturbed by the machine);
// - a ratio (e.g. ours / libapriltag-d1) is taken per image and summarised by its geometric mean over
//   the set, with a 95 % interval from the spread of the log ratios (t-approximation): one big or
//   one slow image cannot stand for the set.
// Wall times in milliseconds; megapixels = width x height / 10^6.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace tagbench::bench {

struct SpeedImage {
  std::string name;  // file name or a description of the generated image
  cv::Mat gray8;     // 8-bit gray; empty when the image could not be read (the row says so, no timing)
};

// A named set whose images are produced one at a time (the corpus is too large to hold at once).
struct ImageSet {
  std::string name;    // "corpus", "raytrace", "realistic", "scenes"
  std::string source;  // where the images came from (settings column of the CSV)
  std::size_t size = 0;
  std::function<SpeedImage(std::size_t)> image;  // index 0..size-1
  double input_gamma = 2.2;  // the images' encoding (ComparatorSetup::input_gamma): 1 for renders
};

// Every image of a corpus folder (its manifest.tsv, else every image file under it; corpus_tools).
ImageSet corpus_set(const std::filesystem::path& corpus_dir);
// The PNG frames in a ray-traced frame cache (bench/raytrace/render.hpp), in file-name order.
ImageSet raytrace_cache_set(const std::filesystem::path& cache_dir);
// `frames` frames of the realistic set (bench/realistic/realistic_set.hpp) at its default settings
// with this seed and family.
ImageSet realistic_set(int frames, std::uint64_t seed, const std::string& family);
// make_scene (bench/scenes.hpp) images: for every size, `per_size` scenes of 6 tags of `family`,
// seeds 1..per_size.
ImageSet scene_set(const std::vector<std::pair<int, int>>& sizes, int per_size, const std::string& family);

// At most `max_images` of the set's images, evenly spread over it (images 0, n/k, 2n/k, ...); the
// set itself when it has no more (or max_images is 0).
ImageSet spread_subset(ImageSet set, std::size_t max_images);

struct SpeedOptions {
  std::vector<std::string> detectors;  // comparator names (bench/raytrace/comparators.hpp)
  std::string family = "36h11";        // what every detector looks for
  int repeats = 1;                     // timed runs per image and detector, the fastest kept (>= 1)
};

struct SpeedRow {
  std::string set, image, detector;
  std::size_t index = 0;  // the image's index in its set
  int width = 0, height = 0;
  bool readable = true;
  double ms = 0;           // fastest of the repeats
  std::size_t found = 0;   // detections of the family
};

struct SpeedProgress {
  std::string set;
  std::size_t done = 0, total = 0;
};

// Times every detector on every image of the set. Throws std::invalid_argument for an unknown
// detector or no detector. `progress`, if given, is called after each image.
std::vector<SpeedRow> time_image_set(const ImageSet& set, const SpeedOptions& options,
                                     const std::function<void(const SpeedProgress&)>& progress = {});

struct SpeedSummary {
  std::string set, detector;
  std::size_t images = 0;     // readable images timed
  double megapixels = 0;      // summed over them
  double total_ms = 0, median_ms = 0, mpx_per_s = 0;
  std::size_t found = 0;      // detections summed over the set
};
std::vector<SpeedSummary> summarise_speed(const std::vector<SpeedRow>& rows);

struct SpeedRatio {
  std::string set, detector, peer;
  std::size_t images = 0;
  double geometric_mean = 0, ci_lo = 0, ci_hi = 0;  // of detector ms / peer ms, per image
  double median = 0, share_faster = 0;              // median per-image ratio; share of images below 1
};
// One entry per (set, pair) whose two detectors were both timed on the set's images.
std::vector<SpeedRatio> speed_ratios(const std::vector<SpeedRow>& rows,
                                     const std::vector<std::pair<std::string, std::string>>& pairs);

// CSV texts (header row first); `settings` is appended to every row as its last column.
std::string speed_rows_csv(const std::vector<SpeedRow>& rows, const std::string& settings);
std::string speed_summary_csv(const std::vector<SpeedSummary>& summary, const std::vector<SpeedRatio>& ratios,
                              const std::string& settings);

}  // namespace tagbench::bench
