#pragma once
// A second look at small candidate quads that did not decode (beyond AprilTag 2/3; issue 17, small
// low-contrast tags of the realistic set). The adaptive threshold (threshold.hpp) classes each pixel
// against its 6 x 6 px neighbourhood; on a 20-24 px tag in shade or on a dark ground the 2-3 px white
// ring then breaks, the black square's dark component leaks into the ground, and the quad fitted to
// the group is the tag plus some ground, or the outline of the lighter card the tag is printed on:
// a quad near the tag that reads as noise. Here each such quad's neighbourhood is classed again with
// ONE threshold, Otsu's (the split of the region's histogram that maximises the between-class
// variance), which puts the white ring and card on one side and the ink on the other whatever the
// local window sees; the region's components, boundaries and quad fit (the threshold stage's own,
// components.hpp ... quad_fit.hpp) give new candidate quads, refined on the image (edge_refine.hpp).
//
// Coordinates: image pixels, centres at integer coordinates; quads as in quad_search.hpp.
#include <span>
#include <vector>

#include "image.hpp"
#include "quad_search.hpp"
#include "threshold_quads.hpp"

namespace tagbench {

struct SecondLookOptions {
  bool enabled = false;       // off here; the default profile turns it on (DetectorOptions::second_look)
  double max_size_px = 48;    // only quads whose bounding box's longer side is at most this, > 0
                              // (default profile: 80; 48 found 4 fewer of 1384 realistic tags than 64,
                              // 64 4 fewer than 80)
  // ... and at least this, >= 0 (default profile: 16). Quads under 16 px were half of the looks on the
  // realistic set and none of them gave a quad that decoded (seeds 1 and 2, 200 frames each: 56,000
  // such looks); leaving them out gave the same detections there and on seed 3, and in every sweep,
  // for 6 % less time (issue 17, session 18).
  double min_size_px = 0;
  double margin_px = 3;       // the region: the quad's bounding box grown by this on every side, >= 0
  // Otsu's two classes' means must differ by at least this ([0, 1] intensities): flat regions are skipped.
  double min_class_gap = 6.0 / 255.0;
  double min_corner_change_px = 1.0;  // a new quad within this of the old one at every corner is dropped, px
  // Otsu's histogram from the pixels inside the quad only (else the whole region): a tag's card on a
  // darker ground otherwise puts the ground in one class and card and ink in the other.
  bool inside_only = true;
  // Whether it also runs when quads are found at half resolution (DetectorOptions::half_resolution).
  // Off: there it found 655 -> 758 of 1384 realistic tags (20-24 px 73 -> 102 of 188) but took the
  // half-resolution profile from 0.87 to 1.23 of libapriltag d2's time on the realistic set and 0.70
  // -> 0.90 on the corpus (target <= 1.0; issue 17, session 8).
  bool at_half_resolution = false;
  // No look at a quad the decoder's border pre-filter refused (PayloadOptions::quick_reject): half of
  // the looks of session 18's count, 17 of their 60,000 productive. The default profile: on (realistic
  // seeds 1 / 2, 200 frames: 1098 -> 1097 and 1046 -> 1046 tags, 20-24 px the same; 1.3 % less time).
  bool skip_border_rejected = false;
};

// Whether a quad gets a second look under `opt`: one that did not decode, and (skip_border_rejected)
// was not refused by the border pre-filter.
bool wants_second_look(bool decoded, bool border_rejected, const SecondLookOptions& opt);

// New candidate quads for `quads` (full-resolution corners) whose entry in `look` is true. `fit` and
// `refine` are the threshold stage's (ThresholdQuadOptions::fit, ::refine; sizes in full-resolution
// px); dark_eight as ThresholdQuadOptions::dark_eight_connected.
std::vector<Quad> second_look_quads(const ImageF& img, std::span<const Quad> quads, const std::vector<bool>& look,
                                    const ThresholdQuadOptions& tq, const SecondLookOptions& opt);

// Otsu's threshold of `values` in [0, 1] (256 bins): the split maximising the between-class variance,
// returned with the two classes' means. For tests and the unit above.
struct OtsuSplit {
  double threshold = 0, dark_mean = 0, light_mean = 0;
};
OtsuSplit otsu_split(std::span<const float> values);

}  // namespace tagbench
