#pragma once
// Our detector with options changed, for experiments: the part of a comparator name after the base
// name ("tagbench", "tagbench-half", "tagbench-paper", "tagbench-paper-half", "tagbench-thorough"),
// '/'-separated KEY=VALUE pairs, e.g. "tagbench/finder=gradient/sharpen=0.25" or "tagbench/look=0"
// (each change of the default profile measured on its own in the sweeps and the realistic set,
// comparators.hpp).
//
// The keys and the option each sets (detector.hpp; values in that option's units, booleans as 0/1):
//   finder (threshold|gradient), reader (area|point), k, extent, sharpen, small_px, small_sharpen:
//     the quad finder and the area payload reader; refine, gamma, refine_iter, refine_spacing: edge
//     refinement; hamming (bits corrected in every family), byfamily; tile, contrast, low_contrast,
//     weber, minpix, minwidth, tblur, nblur, nblur_min, nblur_sigma (the noise-chosen blur), minpts,
//     maxima, mse, dark8, oneside, occl, refit, agree: the
//     threshold quads and the occlusion refit; margin (min decision margin); photo, photo_*: the
//     photometric refinement; pguard, pguard_*: its guard; posechoice, posechoice_*: the pose choice;
//     bent, bent_*: folded tags; outer, outer_*, ring_*: the outer-outline fallback; look, look_*: the
//     second look; soft, soft_*: the soft decoder (soft_decode.hpp); cref, cref_*: the code refit
//     (code_refit.hpp); dfr, dfr_*: the defocus reading (defocus_read.hpp; dfr_rmax: radii 0 and
//     0.6 up to it in steps of 0.1; dfr_radii: the radii as a colon-separated list, 0:0.7:0.9:1.1);
//     cc, cc_min, cc_max, cc_move, cc_rej, cc_spare, cc_n, cc_support, cc_contrast: the corner completion (corner_completion.hpp).
//     detector_variants.cpp maps every key to its field.
#include <span>
#include <string>

#include "detect/detector.hpp"

namespace tagbench::bench {

// Applies `spec` ("KEY=V/KEY=V...", possibly empty) to `o`. Throws std::invalid_argument naming the
// detector `name` for a pair without '=' or an unknown key.
void apply_detector_variant(DetectorOptions& o, const std::string& spec, const std::string& name);

// The default profile with command-line arguments applied, each one KEY=V (the experiment drivers'
// `[KEY=V ...]`); throws as apply_detector_variant.
DetectorOptions detector_options_from_args(std::span<char* const> args);

}  // namespace tagbench::bench
