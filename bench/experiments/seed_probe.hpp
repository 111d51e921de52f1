#pragma once
// Issue 17 experiment (session 14): what a seed must give for a tag the threshold stage finds no quad
// for. Both probes end as the detector does: the threshold stage's edge refinement, then decoding
// with the profile's readers. Not part of the library or of make bench (candidate_loss prints them).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "codes/tag_family.hpp"
#include "detect/boundaries.hpp"
#include "detect/detector.hpp"

namespace tagbench::bench {

// The mean of a quad's corners.
Eigen::Vector2d centre_of(const Corners& c);

// Whether p lies strictly inside one of the convex quads (either winding).
bool inside_any(std::span<const Corners> quads, const Eigen::Vector2d& p);

// The largest corner distance between two quads under the best cyclic shift of their corners (px).
double best_corner_match(const Corners& a, const Corners& b);

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

// The same seed with the turn taken from the image (the gradients' dominant direction mod 90 degrees
// around the centre, `turn_deg`) and three sides (0.9, 1, 1.1 x): how many of the three decode.
int centre_scale_turn_decodes(const ImageF& img, const Corners& truth, int id, const TagFamily& family,
                              const DetectorOptions& opt, double& turn_deg);

// Of the 16 quads made from `quad` by moving one corner by step_px along x or y, how many decode to
// `id` (refined first when `refine`).
int jitter_decodes(const ImageF& img, const Corners& quad, int id, const TagFamily& family, const DetectorOptions& opt,
                   double step_px, bool refine);

// Whether the payload's light cells give the seed: the hull of every boundary group inside the tag
// (box under 0.8 x the tag, centre within 0.45 of a tag of the tag's), its largest quadrilateral scaled
// by 8/6 (the payload is 6 of the black square's 8 cells; also 8/6.5 and 8/5.5), refined and decoded.
int payload_hull_decodes(const ImageF& img, const BoundaryGroups& groups, const Corners& truth, int id,
                         const TagFamily& family, const DetectorOptions& opt);

// A whole-frame prototype of that seed: dark blobs of tag size. At every second pixel and each side s in
// `sides`, the mean of the box ring between half-widths 0.45 s and 0.65 s minus the mean of the inner
// box (half-width 0.45 s) (a dark square on a lighter surround, whatever its turn); local maxima over
// position and side above `min_response` (intensity, 0-1), strongest first, none within half a side of
// a stronger one and none whose centre lies in `covered` (the quads already found).
struct BlobSeed {
  Eigen::Vector2d centre;
  double side = 0, response = 0;
};
std::vector<BlobSeed> blob_seeds(const ImageF& img, std::span<const double> sides, double min_response,
                                 std::span<const Corners> covered, int max_seeds);

// A seed read as a tag: squares of side k x the seed's for each k of `side_factors`, turned by the
// gradients' dominant direction, refined and decoded; the first that decodes.
std::optional<Detection> decode_seed(const ImageF& img, const BlobSeed& seed, const TagFamily& family,
                                     const DetectorOptions& opt, std::span<const double> side_factors);

}  // namespace tagbench::bench
