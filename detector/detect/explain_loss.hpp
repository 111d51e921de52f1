#pragma once
// Where a tag was lost: given a tag's true place (its corners) and a detection's trace, the stage
// of the pipeline at which that tag dropped out (issue 17: the loss-stage column of the sweeps and
// `tagbench detect --explain`).
//
// The stages, first to last, and how each is told from the trace (DetectorTrace, with
// quad_outcomes):
//   no_cluster     no gradient cluster has pixels along the tag's border (within `tolerance` of its
//                  sides): the segmentation saw no edge there (options.quad_finder kGradient only; the
//                  threshold quad finder's losses before a quad are all no_quad)
//   no_segment     clusters along the border, but fitted segments on fewer than 4 of the sides; the
//                  explanation says on how many ("segments on 2 of 4 sides")
//   no_quad        segments on all 4 sides (or, for a quad finder without segments, simply no
//                  candidate quad there) but no candidate quad whose corners match the tag's
//   quad_rejected  a matching quad was refused before its payload was read: the border pre-filter,
//                  a degenerate homography, or cells outside the image / no border contrast
//   misread        a matching quad was read, but no family decoded it within its bits corrected; the
//                  explanation gives how many bits of the tag's own code were read wrong
//   wrong_id       a matching quad decoded as another id or family
//   duplicate      it decoded right but a nearby detection of the same id, or of another id over the
//                  same quad (suppress_overlaps), was kept instead
//   below_margin   it decoded right but its decision margin was under min_decision_margin
//   withdrawn      it decoded right, then the occlusion refit withdrew it (occlusion_refit.hpp): a
//                  side disagreed with the decoded tag and could not be re-fitted (DetectorTrace::withdrawn
//                  holds the detection, as decoded)
//   detected       a detection of the right family and id matches the corners
// A quad "matches" when each of its corners lies within `tolerance` pixels of the tag's corner it
// stands for (some cyclic order); the most advanced matching quad speaks for the tag.
//
// Conventions: image pixels with centres at integer coordinates; corners in printed order TL, TR, BR,
// BL of the black square (detector.hpp).
#include <span>
#include <string>

#include "codes/tag_family.hpp"
#include "detect/detector.hpp"

namespace tagbench {

enum class LossStage {
  kNoCluster,
  kNoSegment,
  kNoQuad,
  kQuadRejected,
  kMisread,
  kWrongId,
  kDuplicate,
  kBelowMargin,
  kWithdrawn,  // decoded right, then withdrawn by the occlusion refit (its sides disagree with the tag)
  kDetected,
};

// "no_cluster", "no_segment", ... "detected" (the CSV column's words).
const char* loss_stage_name(LossStage s);

struct TagTruth {
  const TagFamily* family = nullptr;  // the tag's family (must not be null)
  int id = 0;
  Corners corners;  // printed TL, TR, BR, BL, pixels
};

struct LossExplanation {
  LossStage stage = LossStage::kNoCluster;
  int sides_with_segment = -1;  // no_segment / no_quad: sides (0..4) with a segment along them; -1 otherwise
  int bits_wrong = -1;          // misread / wrong_id: bits of the tag's code read wrong; -1 otherwise
  std::string text;             // one line for people, e.g. "payload misread: 4 bits wrong (3 corrected for 36h11)"
};

// The default tolerance: 2 px, or 15 % of the tag's mean side when that is larger.
double default_loss_tolerance(const Corners& corners);

// `trace` and `detections` must come from one detect() call with these `options` (min_decision_margin,
// max_hamming); tolerance <= 0 means default_loss_tolerance.
LossExplanation explain_loss(const TagTruth& truth, const DetectorTrace& trace, std::span<const Detection> detections,
                             const DetectorOptions& options, double tolerance = 0);

}  // namespace tagbench
