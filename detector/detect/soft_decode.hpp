#pragma once
// Beyond the paper: soft-decision decoding of a payload the hard decoder refused (issue 17: small,
// low-contrast tags whose reading has more wrong bits than the family corrects).
//
// The reader (payload_decode.hpp, payload_area.hpp) gives each payload cell a signed confidence
// z = (I - threshold) / ((white - black) / 2). Its scale varies from tag to tag (sharpening
// overshoots, a payload brighter or darker than the rings' models), so the confidences are first
// divided by their mean magnitude over the payload, then each magnitude is capped at
// `confidence_cap` (one very sure cell must not outvote several):  w_i = min(|z_i| / mean|z|, cap).
// If the cells are the printed bits (+-1 in these units) plus Gaussian noise of a fixed sigma, a
// codeword's log-likelihood is, up to a constant, -(2 / sigma^2) D(w), with the weighted distance
//     D(w) = sum of w_i over the cells whose hard bit disagrees with codeword w,
// so the likeliest codeword is the one of least D (D1), and the log-likelihood ratio of it over the
// runner-up (D2) is proportional to D2 - D1. Every rotation of every code is a hypothesis of its own.
//
// Acceptance (all must hold): the family's minimum Hamming distance is at least min_family_hamming;
// the best codeword disagrees with at most max_bit_errors hard bits; it fits (D1 <= max_distance:
// what disagrees is weak); and it is far likelier than any other (D2 - D1 >= min_gap).
// Calibration (bench/experiments/soft_calib.cpp; issue 17, session 9): the payloads the hard
// decoder refused among the default detector's quads on all 1182 corpus images (37158, none a tag)
// and on realistic frames 200-499 (30517 away from any tag, 805 on a tag but not reading it), and
// those tags' truth-corner readings: with max_bit_errors 6 and no refused payload of any kind within
// 0.5 of both bounds (none with D1 <= 2 and D2 - D1 >= 4), 60 of the 243 refused true readings pass.
#include <optional>
#include <span>

#include "../codes/tag_family.hpp"
#include "homography.hpp"
#include "payload_decode.hpp"

namespace tagbench {

struct SoftDecodeOptions {
  // Default profile on; DetectorOptions::paper(): off. Runs only on quads no family decoded hard.
  bool enabled = true;
  // Families with a smaller minimum distance are never soft decoded. 10: 36h11 and 36h10 (on all
  // the corpus' refused 36h10 payloads, 37157, none passes the rule or lies within 0.5 of it; on the
  // realistic set in 36h10, 962 -> 971 of 1384, no wrong id); not 25h9 (2 of its 39384 refused corpus
  // payloads pass) nor 16h5.
  int min_family_hamming = 10;
  int max_bit_errors = 6;        // hard bits the best codeword may disagree with
  double max_distance = 1.5;     // D1, in mean confidences
  double min_gap = 4.5;          // D2 - D1, in mean confidences
  double confidence_cap = 1.5;   // the cap on w_i
  // No soft decoding of a quad flatter than this: its area over its mean side squared (1 for a square,
  // 0.89 at 60 degrees of tilt, 0.5 at 80); 0 = off. Session 33: a 0.27 sliver was the one 36h11
  // false detection on the corpus with the threshold blur of ThresholdQuadOptions::noise_blur on;
  // with 0.4 none, and realistic seed 1 (plain and sharpened) and the angle sweep row for row the
  // same. Variant key `soft_area`; decode_quads.hpp applies it.
  double min_area_ratio = 0.4;
  // No soft decoding of a quad whose opposite sides differ more than this: the shorter of each pair
  // over the longer, the smaller of the two ratios (1 for any parallelogram; a tag seen from far
  // enough for its payload to be hard to read is imaged nearly affinely); 0 = off, [0, 1]. Variant
  // key `soft_opp`. 0.8 by default since session 37 (measured in session 36: realistic seeds 1 / 2,
  // 200 frames, every tag the same and seed 2's one false detection gone; with the ring check's
  // outward slack, OuterOutlineOptions, it removes the 36h11 corpus false detection the slack let
  // through, a 0.72 quad soft decoded six bits off). The paper profile does not soft decode.
  double min_opposite_ratio = 0.8;
};

// The smaller of a quad's two opposite-side ratios (shorter / longer; 0 for a degenerate side).
double quad_opposite_ratio(const Corners& corners);

// A quad's area over its mean side squared (0 for a degenerate one): how far from a face-on square.
double quad_area_ratio(const Corners& corners);

// The best and second-best codewords (index 4 * id + rotation into TagFamily::rotated_words()) for
// the confidences z (row-major, MSB first: z[k] belongs to bit d*d-1-k; a cell is a hard 1 when
// z > 0), by weighted distance; ties go to the lower index. Exact: words that cannot beat the
// runner-up (the sum of their p smallest weights already reaches it, p their hard-bit distance) are
// skipped. best = -1 when z is not family.bits() long or all zero.
struct SoftMatch {
  int best = -1, second = -1;
  double best_distance = 0, second_distance = 0;  // D1, D2
  int best_bit_errors = 0, second_bit_errors = 0;
};
SoftMatch soft_match(const TagFamily& family, std::span<const float> z, const SoftDecodeOptions& opt = {});

// The decode of `reading` (family.payload_width() wide) when the acceptance rule above holds.
// DecodeResult::hamming is the best codeword's hard-bit distance.
std::optional<DecodeResult> soft_decode(const TagFamily& family, const PayloadReading& reading,
                                        const SoftDecodeOptions& opt = {});

}  // namespace tagbench
