#pragma once
// Beyond the paper (issue 17; DetectorOptions::linear_corners, default profile on, paper() off): the
// sides of every decoded tag located once more on linear intensities.
//
// Cameras store intensities gamma-encoded (sRGB and most JPEGs: value = linear^(1/gamma), gamma about
// 2.2). Blurred and then encoded, a dark-to-light step is lopsided: the encoding stretches its dark
// end, so its steepest part, where the edge refinement puts the side (edge_refine.hpp), moves toward
// the dark side, and a black square comes out smaller than it is. Here each decoded tag's sides are
// re-located (edge_refine's scan) on the tag's neighbourhood with every pixel raised to `gamma`
// (encoded -> linear) before it is interpolated, over a range set by the family's own cell. Which
// tags are decoded is decided before, on the image as it is; only their corners move. A no-op when
// gamma is 1 (linear input: renders with POV-Ray's File_Gamma 1, raw sensor data).
//
// Units: pixels (centres at integer coordinates); corners in the Detection convention.
#include <span>
#include <vector>

#include "../codes/tag_family.hpp"
#include "edge_refine.hpp"
#include "image.hpp"

namespace tagbench {

struct Detection;  // detector.hpp

struct LinearCornerOptions {
  bool enabled = true;               // default profile on; DetectorOptions::paper(): off
  double max_corner_shift_px = 1.0;  // a larger move keeps the corners as they were (the encoding's
                                     // bias is a fraction of a pixel; more is another edge)
};

// Each detection whose family is among `families`: its corners (with homography and centre) replaced
// by those refine_quad_edges finds with `refine`'s scan (its gamma unused) and the family's cells across
// on the linearised neighbourhood, when it succeeds within opt.max_corner_shift_px; the others left
// alone. gamma == 1 (or not finite and > 0): nothing.
void refine_corners_linear(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                           double gamma, const EdgeRefineOptions& refine, const LinearCornerOptions& opt);

}  // namespace tagbench
