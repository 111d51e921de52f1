#pragma once
// Issue 17 experiment (session 14): what a seed must give for a tag the threshold stage finds no quad
// for. Both probes end as the detector does: the threshold stage's edge refinement, then decoding
// with the profile's readers. Not part of the library or of make bench (candidate_loss prints them).
#include <cstdint>

#include "codes/tag_family.hpp"
#include "detect/boundaries.hpp"
#include "detect/detector.hpp"

namespace tagbench::bench {

// Of `trials` quads made from the true corners each moved by `shift_px` in a random direction (seeded
// by `seed`), how many refine and decode to the tag's `id`.
int perturbed_truth_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                            const DetectorOptions& opt, double shift_px, int trials, std::uint32_t seed);

// Whether a quad taken from the convex hull of one boundary group near the tag (its largest inscribed
// quadrilateral over the hull's vertices; groups whose box is 0.5-1.6 x the tag's and whose centre lies
// within half a tag of the tag's) refines and decodes to `id`, as it is or shrunk by 8/10 (`shrunk`:
// the group outlined the white ring too). `groups_near` counts the groups tried.
bool hull_seed_decodes(const ImageF& img, const BoundaryGroups& groups, const Corners& truth, int id,
                       const TagFamily& family, const DetectorOptions& opt, int& groups_near, bool& shrunk);

// How many squares at the tag's true centre, with the side of its true area and turned by every
// `angle_step_deg` in [0, 90), refine and decode to `id` (the seed a blob detector could give).
int centre_scale_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                         const DetectorOptions& opt, double angle_step_deg);

// Whether the payload's light cells give the seed: the hull of every boundary group inside the tag
// (box under 0.8 x the tag, centre within 0.45 of a tag of the tag's), its largest quadrilateral scaled
// by 8/6 (the payload is 6 of the black square's 8 cells; also 8/6.5 and 8/5.5), refined and decoded.
int payload_hull_decodes(const ImageF& img, const BoundaryGroups& groups, const Corners& truth, int id,
                         const TagFamily& family, const DetectorOptions& opt);

}  // namespace tagbench::bench
