#pragma once
// The default profile's stages 1-5 (beyond the paper): candidate quads from the threshold quad stage
// (threshold_quads.hpp: adaptive threshold, connected components, boundaries, quad fit, edge
// refinement on the unblurred image) instead of the paper's gradient clusters. A QuadFinder
// (detector.hpp), chosen by DetectorOptions::quad_finder = QuadFinderKind::kThreshold.
//
// Uses opt.threshold_quads, with opt.half_resolution as its `halve` (the half-resolution variant
// of the profile) and opt.decode_sigma for the decoding image as find_quads_in_image does. Quads
// and segments are in full-resolution coordinates; there are no segments (the stage has none).
// `timings` receives threshold + components as `segmentation`, boundaries + fit as `quads`, the
// refinement as `line_fit`; `trace` receives the quads (segmentation_input = the input or its half),
// the main pass's pixel classes and its boundary groups.
#include "detect/detector.hpp"
#include "detect/find_quads_in_image.hpp"

namespace tagbench {

FoundQuads find_threshold_quads_in_image(const ImageF& gray, const DetectorOptions& opt, DetectorWorkspace& workspace,
                                         StageTimings* timings = nullptr, DetectorTrace* trace = nullptr);

}  // namespace tagbench
