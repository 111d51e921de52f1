#pragma once
// A dark component's whole outline (beyond AprilTag 2/3; issue 17, session 26: small tags of the
// realistic set). Boundary groups are per pair of components (boundaries.hpp), so where the 1-cell
// white ring of a 20-24 px tag is broken into pieces (blur, a darker card, noise), the black border's
// outline is split among as many groups as there are ring pieces: each piece's group holds one or
// two sides, and no group fits a quad; where the border broke instead and the ring is whole, the
// same with the roles swapped. Here the groups that share a dark component (and, by_light, those that
// share a light one) are joined (their points in group order) when the joined outline is of tag size,
// and each joined group is fitted by its outer outline, then its innermost outward outline
// (outline_only; else by the whole chain of fit_quads); the quads whose centre no tag found so far
// covers are edge-refined on the image and decoded like every candidate. On in the default profile
// (since session 27, with the half-size line quads in place of the coarse pass) and the thorough one
// (realistic seeds 1 / 2: +9 / +5 tags, 20-24 px +1 / +2, 7 % more time there; docs/default-profile.md,
// sessions 26-27).
//
// Coordinates: pixels of the image the groups were found on (doubled in BoundaryGroups); quads
// clockwise on screen (quad_search.hpp).
#include <span>
#include <vector>

#include "boundaries.hpp"
#include "components.hpp"
#include "edge_refine.hpp"
#include "homography.hpp"
#include "image.hpp"
#include "outer_outline.hpp"
#include "quad_fit.hpp"
#include "quad_search.hpp"
#include "threshold_quads.hpp"  // ThresholdQuadOptions::RefineCheck

namespace tagbench {

struct DarkOutlineOptions {
  bool enabled = false;      // off here and in paper(); the default and thorough profiles turn it on
  double min_size_px = 10;   // the joined groups' box: longer side at least this, >= 0
  double max_size_px = 50;   // ... and at most this (px), > 0
  int min_groups = 2;        // a dark component joined only when it has at least this many groups, >= 2
  int max_groups = 8;        // ... and at most this many (a textured blob borders dozens), >= min_groups
  // The outer outline's ring check (OuterOutlineOptions::ring_check) on the joined outlines: off, as
  // the ring of these tags is the broken part (on: 8 of the 19 realistic tags more, seed 1).
  bool ring_check = false;
  bool by_light = true;      // also join the groups that share a light component (a border broken into pieces)
  // A component whose groups are too many or too far apart to join whole (a border broken into
  // pieces that share the white ground, which borders dozens of other groups): its groups at most
  // max_size_px across clustered by overlapping boxes, and each cluster of min_groups..max_groups
  // groups and tag size joined. Off in every profile (session 36, variant key `dq_overlap`; realistic
  // seeds 1 / 2, 200 frames: 1100 -> 1101, 1048 -> 1050 tags, none at 20-24 px, the same time; corpus
  // 16h5 false detections 295 -> 302, 36h11 none. Without the ring check below +4 / +4 tags, 20-24 px
  // +0 / +1, but a 36h11 false detection on the corpus; each two overlapping groups joined instead of
  // whole clusters, +5 / +5, 20-24 px +0 / +2, for 6-8 % more time and a false detection.)
  bool overlap_clusters = false;
  // The fit's ring check (QuadFitOptions::outer.ring_check, where it is on) asked of the overlap
  // clusters' outlines, whatever ring_check says: their ring is whole, their border the broken part.
  bool overlap_ring_check = true;
  // Pairs of groups that each gave no quad alone (fit_quads' gave_quad) and whose boxes, each at most
  // max_size_px across and grown by pair_margin_px, overlap, joined when the pair's box is of tag size,
  // whatever components they share: a border split into pieces by a ring broken in two places and a
  // border broken once. Fitted like an overlap cluster (its ring check). Off in every profile (issue
  // 17, session 40; docs/default-profile.md): realistic seeds 1 / 2 (200 frames) 1102 -> 1106 and
  // 1051 -> 1053 tags, 20-24 px 173 -> 174 and 179 -> 179, for +12 % detector instructions; with
  // pair_min_points 24 and pair_min_share 0.5, +3 / +2 tags (20-24 px none) for +4.5 %.
  bool failed_pairs = false;
  double pair_margin_px = 1.0;  // >= 0
  int pair_min_points = 0;       // each group of a pair has at least this many boundary points, >= 0
  double pair_min_share = 0;     // each group's box's longer side at least this share of the pair's, [0, 1]
  // Each joined outline fitted only by its outer outline (then its innermost outward outline), not by
  // the whole chain of fit_quads (the whole group, one side, the occluded fit): a joined outline
  // holds several outlines by construction.
  bool outline_only = true;
  // The threshold quads' border check before refining (ThresholdQuadOptions::refine_check, where it is
  // enabled: the Detector turns it off where the decoder would not ask the same test of the same
  // image) asked of these quads too: most joined outlines are texture, and refining them all cost more
  // than reading them.
  bool check_before_refining = false;
  // With check_before_refining: a quad the plain test refuses is still refined when this many sides
  // (1..4) pass the test with slack (border_worth_refining); 0: never.
  int slack_sides = 0;
};

struct DarkOutlineScratch {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> by_component;  // (component, group)
  struct Member {
    DoubledBox box;
    std::uint32_t group, parent;
  };
  std::vector<Member> cluster;                                   // overlap_clusters: one component's groups
  std::vector<std::pair<std::uint32_t, std::uint32_t>> members;  // (cluster root, index into cluster)
  std::vector<bool> from_cluster;                                // per joined group: an overlap cluster's
  std::vector<Member> failed;                                    // failed_pairs: the groups (parent unused)
  BoundaryGroups joined;
  std::vector<Quad> fitted;
  EdgeRefineScratch refine;
};

// The quads of the joined outlines of `groups` (found with `components` on `img`), fitted with `fit`,
// whose centre lies inside none of `covered`, each refined on `img` with `refine` (a quad whose
// refinement fails is dropped; with opt.check_before_refining and `check` enabled, one the border
// check refuses is left as fitted, for the decoder's pre-filter to refuse by the same test). Throws
// std::invalid_argument when components and img differ in size.
std::vector<Quad> dark_outline_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                                     std::span<const Corners> covered, const QuadFitOptions& fit,
                                     const EdgeRefineOptions& refine, const DarkOutlineOptions& opt,
                                     QuadFitScratch& fit_scratch, DarkOutlineScratch& scratch,
                                     const ThresholdQuadOptions::RefineCheck& check = {},
                                     std::span<const std::uint8_t> gave_quad = {});

}  // namespace tagbench
