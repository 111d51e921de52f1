#pragma once
// Beyond the paper and AprilTag 3 (off in paper(); in the default profile on the half-size image,
// in thorough() at full resolution; measured in docs/default-profile.md, sessions 22-27): candidate
// quads from straight edges (line_segments.hpp, LSD's method) joined by the
// paper's quad search (quad_search.hpp). A small tag whose white ring is broken or classed with its
// border has no outline among the threshold stage's boundary groups, yet its four sides are short
// straight edges that region growing on gradient directions still finds whole.
//
// Each edge is searched both ways, so a quad may be dark inside (the black square) or light inside
// (a white ring's outer edge on a darker card), or mix the two where the ring is broken on one side;
// the caller reads every quad both as the black square and as a printed square (printed_square.hpp).
// Coordinates: pixel centres at integer coordinates; corners clockwise on screen (quad_search.hpp).
#include <span>
#include <vector>

#include "homography.hpp"
#include "image.hpp"
#include "line_segments.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct LineQuadOptions {
  bool enabled = false;      // both profiles off (see above)
  double max_side_px = 64;   // quads with a longer side are not kept: larger tags have their outline
  double min_side_px = 8;    // every side and diagonal at least this (QuadSearchOptions::min_tag_size)
  // Each quad edge-refined before it is read as the black square; else (default) only the tags it
  // gives, after reading: refined first, a steep tag's far side moved to another edge read 2 bits off
  // as a tag 3-5 px from its place (realistic seed 1, frame 106).
  bool refine_black = false;
  bool refine_inner = true;  // each printed square's inner square refined before it is read
  // The border pre-filter (PayloadOptions::quick_reject) asked of a quad before it is refined, not
  // only after: refining every one of some 380 quads a frame was a third of the line quads' time.
  bool check_before_refining = false;
  // With check_before_refining: an inner square the check refuses is still refined when all four of
  // its sides pass the check with slack (border_contrast_plausible_with_slack, 4 sides): the inner
  // square is placed only as well as its printed square, a pixel or two off. The default profile: on
  // (realistic seeds 1 / 2 / 3, 200 frames: 1098 -> 1100, 1046 -> 1049, 1147 -> 1149 tags, 20-24 px
  // 170 -> 172, 176 -> 177, 212 -> 212; with three sides 1.3 % more time for the same tags on seed 1).
  bool inner_check_slack = false;
  // A tag read from these quads is at most (bits its family corrects - spare_bits) off its code: some
  // 380 such quads a realistic frame are read. 1 since session 46 (36h11 2 bits, 25h9 1, 16h5 exact
  // readings only): realistic seeds 1 / 2 +2 / +0 tags, 25h9 +7, no wrong id and no false
  // detection there or on the corpus; 0 gave a 36h11 false detection on each realistic seed (and in
  // session 22, before the border checks, 1 gave one on the corpus). docs/default-profile.md, session 46.
  int spare_bits = 1;
  // A reading with no bit wrong is kept whatever spare_bits says: else a family correcting no more
  // than spare_bits (16h5 corrects 1) would take no tag at all from these quads, though they are
  // found and read for it.
  bool keep_exact = true;
  // The edges found on the image resampled to this scale (in (0, 1]; 1: as it is; 0.5: its 2 x 2
  // average), their ends mapped back; the quads are then read and refined at full resolution.
  double scale = 1;
  // Also when the detector runs at half resolution (DetectorOptions::half_resolution; the quads still
  // from the edges at `scale` of the full image). The default profile: off.
  bool at_half_resolution = true;
  LineSegmentOptions segments;
};

struct LineQuadScratch {
  LineSegmentScratch segments;
  std::vector<Segment> both_ways;
  ImageF small, blurred, tmp;  // the resampled image (LineQuadOptions::scale)
};

// The quads of `img`'s edges within the size bounds whose centre lies inside none of `covered`
// (the corners of tags already found, any winding). Quads carry observed_perimeter 0: an inferred
// outline must not win duplicate ties against a tag's own quad.
std::vector<Quad> line_quads(const ImageF& img, std::span<const Corners> covered, const LineQuadOptions& opt,
                             LineQuadScratch& scratch);

// Whether q's centre (its corners' mean) lies inside any of `covered` (any winding).
bool centre_covered(const Quad& q, std::span<const Corners> covered);

}  // namespace tagbench
