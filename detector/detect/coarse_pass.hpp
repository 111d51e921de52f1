#pragma once
// A coarse pass of the threshold stage (beyond the paper and AprilTag 3; issue 17, session 25):
// the full-resolution pass is tuned for 12-24 px tags (2 px tiles, a 20/255 contrast floor), and on
// a larger tag of low contrast its 6 x 6 px windows see mostly noise: the border breaks into pieces
// or stays below the floor, and no quad comes out. The same stage on the 2 x 2-averaged image
// (quarter the pixels, half the noise, windows of 12 x 12 full-resolution px) with a lower floor
// classes those tags whole. Its quads whose centre no tag found so far covers are refined on the
// full-resolution image and handed to the decoder like every other candidate.
//
// Coordinates: full-resolution pixels, centres at integer coordinates; quads as in quad_search.hpp.
#include <span>
#include <vector>

#include "homography.hpp"
#include "image.hpp"
#include "quad_search.hpp"
#include "threshold_quads.hpp"

namespace tagbench {

struct CoarsePassOptions {
  bool enabled = false;  // off here and in paper(); the default profile turns it on (detector_options.hpp)
  // The half-size image's contrast floor (ThresholdOptions::min_contrast there), [0, 1]. At 20/255
  // (the main pass's) it found 12 more realistic tags instead of 19 (seed 1, occlusion_fit on,
  // min_tag_px 0).
  float min_contrast = 10.0f / 255.0f;
  // The low-contrast pass (low_contrast_quads.hpp) on the half-size image too: the same tags.
  bool low_contrast = false;
  // The occlusion-tolerant fit (QuadFitOptions::tolerate_occlusion, when the main pass has it): on,
  // 5 more tags of 1384 (seed 1) for a quarter more of the pass's time.
  bool occlusion_fit = false;
  // Quads narrower than this (full-resolution px; QuadFitOptions::min_tag_width) are not kept, >= 0:
  // the main pass is the one for small tags. 20 px: the same tags as 0 for a sixth less time.
  double min_tag_px = 20;
};

// The coarse pass's quads (full-resolution corners, refined on `gray` when main.refine_edges) whose
// centre lies inside none of `covered`. `main` is the main pass's options: the coarse pass is the
// same stage with halve on and opt's floor.
std::vector<Quad> coarse_pass_quads(const ImageF& gray, const ThresholdQuadOptions& main, std::span<const Corners> covered,
                                    const CoarsePassOptions& opt, ThresholdQuadWorkspace& ws);

}  // namespace tagbench
