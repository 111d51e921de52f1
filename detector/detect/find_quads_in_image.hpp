#pragma once
// Stages 1-5 of the detector (paper section III-A and III-B): blur (and halve), gradients,
// clusters, segments, quads. Detector::detect and the corpus's candidate quads
// (corpus_tools/candidates.hpp) both call this one function, so the quads they see are the same.
//
// Conventions as in detector.hpp: pixel centres at integer coordinates; segments and quads are in
// the input image's (full-resolution) coordinates, also with half_resolution.
#include <vector>

#include "detect/detector.hpp"
#include "detect/image.hpp"
#include "detect/line_fit.hpp"
#include "detect/quad_search.hpp"

namespace tagbench {

struct FoundQuads {
  // The image payloads are read from: the input itself, or its separately blurred copy in the
  // workspace (DetectorOptions::decode_sigma > 0). Valid while the input and the workspace are.
  const ImageF* decode_image = nullptr;
  std::vector<Segment> segments;  // full-resolution coordinates
  std::vector<Quad> quads;
};

// Uses only the image options of `opt` (seg_sigma, decode_sigma, half_resolution, segmentation,
// line_fit, quad_search); they must be valid (DetectorOptions::validate). Every per-pixel buffer
// comes from `workspace` (reused from call to call, see DetectorWorkspace). `timings`, if given,
// receives blur, gradient, segmentation, line_fit, quads, segment_count and quad_count (the other
// fields are left alone). `trace`, if given, receives segmentation_input, the gradient images,
// clusters, segments and quads (copies; its other fields are left alone). A QuadFinder
// (detector.hpp).
FoundQuads find_quads_in_image(const ImageF& gray, const DetectorOptions& opt, DetectorWorkspace& workspace,
                               StageTimings* timings = nullptr, DetectorTrace* trace = nullptr);

}  // namespace tagbench
