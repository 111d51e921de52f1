#pragma once
// Corner completion (beyond the paper and AprilTag 3; issue 17). A tag crossed by a hard shadow's
// edge, or touching a dark object at one corner, often gets a candidate quad with three corners on
// the black square and the fourth cut short or pulled along the other outline: it reads 9-20 bits
// off and is lost (realistic set, seed 1: the largest class of readable 24-40 px tags lost,
// docs/default-profile.md, session 47). A small tag is close to a parallelogram in the image, so the
// three good corners predict the fourth: d = a + c - b for the corner d between a and c, b
// opposite. Each quad still undecoded gets its four completions (each corner replaced by the one
// its other three predict), kept when the corner moved by at least min_move_px and the quad stays
// convex; the caller pre-filters, refines and reads them like any candidate quad.
//
// Coordinates: pixels (pixel centres at integer coordinates); corners clockwise on screen, as
// quad_search.hpp.
#include <span>
#include <vector>

#include "image.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct QuadOutcome;  // detector.hpp

struct CornerCompletionOptions {
  bool enabled = false;         // off here; see DetectorOptions::corner_completion
  double min_side_px = 12;      // quads whose shortest side is under this are not completed (px)
  double max_side_px = 64;      // nor those whose longest side is over this: a large tag is not a parallelogram
  double min_move_px = 1.5;     // a completion moving its corner less than this is the same quad again (px)
  bool border_rejected = false;  // also complete quads the border pre-filter refused (else only those read)
  // The completed corner must have the border behind it: along the part of each of its two sides that
  // the completion added (from where the old side's line is nearest the new corner, i.e. the half
  // next to it), samples half a ring cell inside must be darker than those half a ring cell outside
  // by min_contrast (image units, [0, 1]) at no fewer than min_support of support_samples points.
  // Most quads on texture fail it; a tag whose corner was cut by a shadow keeps its border's local
  // contrast in the shade.
  int support_samples = 8;         // per side, >= 1
  double min_support = 0.75;       // share of the 2 x support_samples pairs, [0, 1]
  double min_contrast = 4.0 / 255;
  // A tag read from a completed quad is at most (bits its family corrects - spare_bits) off: the
  // corner is made up, so the reading is held to the line quads' stricter test.
  int spare_bits = 1;
};

// The completions of every quad whose outcome is kNotDecoded (and kBorderRejected with
// opt.border_rejected) with sides in [min_side_px, max_side_px] and its centre inside none of
// `covered`. `quads` and `outcomes` are parallel (a size mismatch gives none). Completed quads carry
// segments -1 and observed_perimeter 0 (an inferred outline never wins a duplicate tie).
// `img`: the image the quads are read on; d: the largest payload width tried (its ring cells are
// the thinnest).
std::vector<Quad> completed_quads(const ImageF& img, int d, std::span<const Quad> quads,
                                  std::span<const QuadOutcome> outcomes, std::span<const Corners> covered,
                                  const CornerCompletionOptions& opt);

// The support test above for corner k of the completed quad c (either winding: the sides' outward
// normals point away from its centre).
bool completion_supported(const ImageF& img, int d, const Corners& c, int k, const CornerCompletionOptions& opt);

// The quad with corner k replaced by the parallelogram completion of the other three.
Corners complete_corner(const Corners& q, int k);

}  // namespace tagbench
