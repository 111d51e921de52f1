#pragma once
// Beyond the paper: a quad read a few bits too far from a code gets one more chance, placed by that
// code's printed pattern (issue 17, the realistic set's misread small tags). A small tag's quad from
// the threshold stage can sit 1-4 px off the tag (a corner pulled along a blurred side, a ring merged
// with the ground); its payload, read through that quad, then misses the code by more bits than the
// family corrects. Here, for a quad that was read but decoded by no family (QuadOutcome kNotDecoded):
//   1. hypothesis: the likeliest code under the cells' confidences (soft_decode.hpp), when it is
//      within max_bits of the reading (more than the family corrects) and the cells it disagrees with
//      are weak (max_weak_distance), for each family whose minimum Hamming distance is at least
//      min_family_hamming;
//   2. placement: the quad's corners, in that code's rotation, refined photometrically against that
//      code's whole printed pattern (photometric_refine.hpp, with a wider reach than the final
//      refinement's: `refine`);
//   3. test: the payload read again through the refined corners (payload_area.hpp) must decode,
//      within the family's corrected bits less spare_bits, to the same code in the same rotation.
// The refinement is fitted to the hypothesis, so step 3 is not an independent reading; what keeps a
// false hypothesis out is that a homography (8 parameters) cannot make a 36-bit reading agree with a
// code it is far from, and only families with a large minimum distance are tried (on the corpus,
// results/fp_detectors.csv measures what it lets through). Flat tags that decode never reach
// this stage: it costs nothing on them.
//
// A detection found here carries the refined corners (TL, TR, BR, BL of the printed tag, as
// decode_quads.hpp), their homography, the re-read's Hamming distance and decision margin.
#include <span>
#include <vector>

#include "../codes/tag_family.hpp"
#include "image.hpp"
#include "payload_area.hpp"
#include "photometric_refine.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct Detection;    // detector.hpp
struct QuadOutcome;  // detector.hpp

struct CodeRefitOptions {
  bool enabled = true;          // DetectorOptions::paper(): off
  int max_bits = 7;             // the hypothesis at most this many bits from the reading
  int min_family_hamming = 10;  // only families at least this far apart (36h11, 36h10; not 25h9, 16h5)
  // The re-read must decode within the family's corrected bits less this many: a placement fitted to
  // the hypothesis leans the reading toward it, so the test is stricter than a first reading's.
  int spare_bits = 1;
  // The hypothesis is the likeliest codeword under the cells' confidences (soft_match,
  // soft_decode.hpp), tried only when the confidence-weighted distance D1 of the cells it disagrees
  // with is at most this (in mean confidences; soft decoding accepts 1.5 unverified): most quads on
  // texture fail it, and each one tried costs a refinement (ray-traced frames at half resolution:
  // +6.7 % time without this test, none measurable with it; realistic set 1012 of 1384 tags at 3,
  // 1014 at 4.5 or without the test, 1007 at 2, seed 2 972 at 3 and 974 at 4.5; sessions 15-16).
  double max_weak_distance = 4.5;
  double min_side_px = 8;       // quads whose shortest side is under this are left alone (px)
  double max_side_px = 64;      // and those whose longest side is over this (px): a large tag's quad is
                                // accurate already, and its refinement costs more
  // The placement's refinement: more steps and a wider reach than the final refinement's, which
  // starts from corners already within a fraction of a pixel.
  PhotometricRefineOptions refine = [] {
    PhotometricRefineOptions r;
    r.iterations = 5;
    r.initial_blur_px = 1.0;
    r.band_px = 2.5;
    r.max_corner_shift_px = 4.0;
    r.max_blur_cells = 1.0;  // placement for reading, not accuracy: a blurred small tag is what this is for
    return r;
  }();
};

// Every quad whose outcome is kNotDecoded, tried as above; the new detections, in quad order. A quad
// decoded here gets its outcome updated (kDecoded, family, id, hamming, margin). `gray` is the
// unblurred image (refined there), `decode_image` the one payloads are read from (decode_quads.hpp);
// `area` the payload reader's options with its min_contrast already set. `quads` and `outcomes` are
// parallel (one outcome per quad); a size mismatch finds nothing. A quad whose centre lies inside a
// detection of `decoded` (the tags found so far) is not tried: tags do not overlap, and a quad there
// is part of a tag already read (its payload's inner squares), which a wide refinement could slide
// onto the tag as another code.
std::vector<Detection> refit_to_nearest_codes(const ImageF& gray, const ImageF& decode_image,
                                              std::span<const Quad> quads, std::span<QuadOutcome> outcomes,
                                              std::span<const Detection> decoded,
                                              std::span<const TagFamily> families, int max_hamming,
                                              bool hamming_by_family, const PayloadAreaOptions& area,
                                              const CodeRefitOptions& opt, PhotometricWorkspace* workspace = nullptr);

}  // namespace tagbench
