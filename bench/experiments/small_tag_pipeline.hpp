#pragma once
// The small-tag experiment's configurable detector (issue 17): the paper's stages called one by one
// (blur, gradient, segmentation, line_fit, quad_search, homography, payload_decode, as
// detect/detector.cpp wires them) with the beyond-the-paper units switched in by a Variant:
// edge_refine (sides re-located on the unblurred image), payload_area (area sampling and decode
// sharpening), the segmentation blur, the bits corrected, a 2x upsampled segmentation. Every quad
// the search found is kept with what became of it, so losses can be attributed (no quad near a tag,
// a quad whose payload was misread by k bits, a wrong id).
//
// Conventions as detect/ (pixel centres at integer coordinates, corners TL, TR, BR, BL printed).
#include <optional>
#include <string>
#include <vector>

#include "codes/tag_family.hpp"
#include "detect/edge_refine.hpp"
#include "detect/homography.hpp"
#include "detect/image.hpp"
#include "detect/payload_area.hpp"
#include "detect/payload_decode.hpp"

namespace tagbench::bench::experiments {

struct Variant {
  std::string name = "paper";
  double seg_sigma = 0.8;        // the paper's sigma
  bool upsample = false;         // segment a 2x (bilinear) upsampled image; quads mapped back
  bool both_scales = false;      // with upsample: also segment at 1x and merge both scales' detections
  double min_mag_scale = 1;      // multiplies SegmentationOptions::min_mag (minMag) on the segmented image
  bool refine_edges = false;     // edge_refine.hpp on the unblurred image, before the homography
  EdgeRefineOptions edge;
  bool area_payload = false;     // payload_area.hpp instead of payload_decode.hpp
  PayloadAreaOptions area;
  int max_hamming = 1;
};

// Parses "name:key=value,key=value" (keys: sigma, up, both, magscale, refine, area, k, extent, sharp, h, range), e.g.
// "best:sigma=0.8,refine=1,area=1,sharp=0.5,h=1". Throws std::invalid_argument on a bad spec.
Variant parse_variant(const std::string& spec);

struct QuadOutcome {
  Corners corners;                      // the quad as searched (clockwise on screen)
  Corners used;                         // the corners the payload was read through (refined or not)
  bool refined = false;                 // refinement accepted
  std::optional<PayloadReading> reading;  // nullopt: failed the border checks
  std::optional<DecodeResult> decoded;  // at the variant's max_hamming
};

struct PipelineDetection {
  int id = -1, hamming = 0;
  double margin = 0;
  Corners corners;  // printed TL, TR, BR, BL
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
};

struct PipelineResult {
  std::vector<QuadOutcome> quads;
  std::vector<PipelineDetection> detections;  // duplicates (same id, close centres) merged
};

PipelineResult run_pipeline(const ImageF& gray, const TagFamily& family, const Variant& v);

// The payload read through given corners with the variant's reader (for the "oracle" reading through
// the true corners: what the payload stage would do with perfect geometry).
std::optional<PayloadReading> read_with(const ImageF& gray, const Corners& corners, int d, const Variant& v);

}  // namespace tagbench::bench::experiments
