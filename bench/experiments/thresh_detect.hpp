#pragma once
// The threshold quad stage (detect/threshold_quads.hpp) composed into a whole detector for the
// issue-17 experiments, outside the library's Detector (which another change restructures):
// gray8 -> to_float_image -> find_threshold_quads -> quick border test -> tag_homography ->
// read_payload -> family decode -> duplicate suppression, the decode half exactly as
// detect/detector.cpp's run() does it (same rules, same defaults), so the two candidate stages are
// compared with everything after them equal. Also a Comparator, so it times like the others.
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>
#include <vector>

#include "codes/tag_family.hpp"
#include "detect/detector.hpp"
#include "detect/payload_decode.hpp"
#include "detect/threshold_quads.hpp"
#include "raytrace/comparators.hpp"

namespace tagbench::bench::experiments {

struct ThreshDetectorOptions {
  std::string family = "36h11";
  int max_hamming = 1;  // as DetectorOptions
  ThresholdQuadOptions quads;
  // A second candidate pass with these options (e.g. the half-size image, whose wider window copes
  // with defocus), its quads added to the first pass's before decoding; duplicates merge in decode.
  std::optional<ThresholdQuadOptions> second_pass;
  // Also add the paper's gradient quads (detect/detector.hpp through its trace: for recall
  // experiments only, the trace copies make its time meaningless).
  bool with_paper_quads = false;
  PayloadOptions payload;
};

struct ThreshFrameStats {
  ThresholdQuadStats quads;
  double ms_convert = 0, ms_decode = 0;
};

class ThreshDetector final : public Comparator {
 public:
  ThreshDetector(std::string name, ThreshDetectorOptions opt);
  ~ThreshDetector() override;
  const ThreshFrameStats& last_stats() const { return stats_; }
  const std::vector<Quad>& last_quads() const { return quads_; }

 private:
  std::vector<Found> detect(const cv::Mat& gray8) override;
  ThreshDetectorOptions opt_;
  TagFamily family_;
  ImageF gray_;
  cv::Mat colour_;
  ThresholdQuadWorkspace ws_, ws2_;
  std::vector<Quad> quads_, quads2_;
  std::unique_ptr<Detector> paper_;
  ThreshFrameStats stats_;
};

// Decodes `quads` on `gray` like detector.cpp: one family, duplicates (same id, centres closer than
// 1/16 of the two perimeters) merged keeping the lower hamming, then the longer observed perimeter.
std::vector<Found> decode_quads(const std::vector<Quad>& quads, const ImageF& gray, const TagFamily& family,
                                int max_hamming, const PayloadOptions& payload);

}  // namespace tagbench::bench::experiments
