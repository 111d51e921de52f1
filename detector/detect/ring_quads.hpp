#pragma once
// Light rings: a printed square's outline from its white ring (beyond AprilTag 2/3; issue 17, small
// tags of the realistic set). On a card darker than the paper, the threshold stage often keeps the
// tag's white ring as one closed light component while the black border, 2-3 px wide and blurred,
// breaks into pieces (or runs into the payload and the ground): no dark-inside group then outlines the
// black square, but the group between the ring and the card outlines the printed square, light inside.
// Here such groups are fitted as light squares; the detector reads each quad as a printed square
// (printed_square.hpp: the black square inside it, per payload width) and decodes that.
//
// Which groups: light inside (the fit's polarity test), a bounding box whose longer side is in
// [min_size_px, max_size_px], a light component covering at most max_fill of the box (a ring covers
// about a third of its box, a cell's width round 10 cells; a light blob of texture most of it), and
// one that also borders something dark inside the box (min_hole: the ring's inner edge). Only the
// main pass's groups (not the second look's or the low-contrast look's).
//
// Realistic set (200 frames, seeds 1 and 2): tags found 1032 -> 1045 and 1000 -> 1013 (20-24 px: 0,
// +3), none lost, no wrong id; about 2 % more time on the realistic frames and on the corpus
// (session 21).
//
// Coordinates: the pixels of the image the groups were found on (doubled in BoundaryGroups,
// boundaries.hpp); quads clockwise on screen (quad_search.hpp).
#include <vector>

#include "boundaries.hpp"
#include "components.hpp"
#include "image.hpp"
#include "quad_fit.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct RingQuadOptions {
  bool enabled = false;      // off here and in the paper profile; the default profile turns it on (detector_options.hpp)
  double min_size_px = 22;   // the group's box: longer side at least this (a 16 px tag's printed square), >= 0
  double max_size_px = 50;   // ... and at most this (a 40 px tag's), > 0
  double max_fill = 0.6;     // the light component's pixels at most this x the box's area, > 0
  // When > 0: only groups whose light component also meets a dark one inside the box (another group
  // of that light component, its box inside this one's and at least min_hole of its width and
  // height): the ring's inner edge. Realistic seeds 1 and 2, tags found beyond printed_square alone:
  // 0 (off) +15 and +14 for 9 % more time on the corpus, 0.2 +13 and +13 for 2 %, 0.5 +9 and +8, >= 0.
  double min_hole = 0.2;
};

// The light-inside quads of the groups of `groups` selected as above, fitted with `fit` (its
// polarity replaced: light inside only), in group order. `components` are those the groups were
// found between (group_boundaries), on an image of img's size (else std::invalid_argument): each
// group's light component is the one on the light side of its first point.
std::vector<Quad> ring_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                             const QuadFitOptions& fit, const RingQuadOptions& opt, QuadFitScratch& scratch);

}  // namespace tagbench
