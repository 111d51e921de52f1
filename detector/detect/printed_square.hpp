#pragma once
// The black square inside a printed square (beyond AprilTag 2/3; issue 17, small tags of the
// realistic set). A tag is printed as its black square plus a white ring one cell wide; on a card
// or face lighter than the paper, and at 2-3 px a cell, the adaptive threshold (threshold.hpp)
// classes the ring dark together with the black border: the candidate quad is then the printed
// square's outline, (d + 4) / (d + 2) times the black square (d = the payload width), and its
// reading is off by a cell everywhere. Here each quad that did not decode gives the quad of the
// black square it would hold if it were a printed square: the homography of the quad (the square
// [-1,1]^2 onto its corners) applied to the corners of [-s, s]^2, s = (d + 2) / (d + 4), once per
// payload width among the families. The decoder judges them like any candidate. The detector hands
// in only the quads that were read but not decoded: one the border pre-filter refused
// (PayloadOptions::quick_reject) is not a printed square on a lighter card, whose grey outer cells
// pass that test as a black ring.
//
// Realistic set (200 frames; seeds 1, 2): 1026 -> 1030 and 995 -> 1000 tags found (20-24 px: +1,
// +2), none lost, no wrong id, +2-3 % time; at half resolution 669 -> 691 and 655 -> 677 (20-24 px:
// +5, +4), 1 lost, +3-4 % time (session 21).
//
// Coordinates: image pixels, centres at integer coordinates; quads as in quad_search.hpp (the new
// quads keep their quad's corner order; their observed_perimeter is 0: none of their outline was
// seen, so of two detections of one tag with equal Hamming distance suppress_duplicates keeps the
// one from a quad that was, which the occlusion refit would otherwise often withdraw).
#include <span>
#include <vector>

#include "quad_search.hpp"

namespace tagbench {

struct PrintedSquareOptions {
  bool enabled = false;  // off here and in the paper profile; the default profile turns it on (detector_options.hpp)
  // The detector refines the corners of the tags these quads give (edge_refine.hpp, with the threshold
  // stage's ThresholdQuadOptions::refine, on the full-resolution image): the inner square is placed
  // only as well as the outer quad was, at half resolution 1.5-3 px off (realistic set, seed 1).
  bool refine_edges = true;
};

// For every quad whose entry in `look` is true (look.size() == quads.size()) and every distinct
// payload width d in `payload_widths` (each >= 1), in that order: the black square inside it read as
// a printed square (see above). Quads with no homography (degenerate corners) give nothing.
std::vector<Quad> black_squares_in_printed_squares(std::span<const Quad> quads, const std::vector<bool>& look,
                                                   std::span<const int> payload_widths);

}  // namespace tagbench
