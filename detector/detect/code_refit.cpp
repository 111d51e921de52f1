#include "detect/code_refit.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "codes/tag_layout.hpp"
#include "detect/decode_quads.hpp"
#include "detect/detector.hpp"
#include "detect/homography.hpp"
#include "detect/soft_decode.hpp"

namespace tagbench {

namespace {

// One family's hypothesis for one reading, placed and tested; the detection if it holds.
std::optional<Detection> try_family(const ImageF& gray, const ImageF& decode_image, const Quad& quad, Code reading,
                                    const TagFamily& family, int corrected, const PayloadAreaOptions& area,
                                    const CodeRefitOptions& opt, PhotometricWorkspace* workspace) {
  // Cheap first: a code within max_bits at all (a scan of the family's words).
  if (const auto near = family.decode(reading, opt.max_bits); !near || near->hamming <= corrected) return std::nullopt;
  // The hypothesis: the likeliest codeword under the cells' confidences (soft_decode.hpp), kept only
  // when the cells it disagrees with are weak (a misplaced quad reads the cells it straddles near
  // their threshold; texture reads its wrong cells as firmly as its right ones).
  const auto H0 = tag_homography(quad.corners);
  if (!H0) return std::nullopt;
  const auto first = read_payload_area(decode_image, *H0, family.payload_width(), area);
  if (!first) return std::nullopt;
  const SoftMatch soft = soft_match(family, first->confidence);
  if (soft.best < 0 || soft.best_bit_errors > opt.max_bits || soft.best_bit_errors <= corrected ||
      !(soft.best_distance <= opt.max_weak_distance))
    return std::nullopt;
  const DecodeResult hypothesis{soft.best / 4, soft.best_bit_errors, soft.best % 4};
  const Corners start = printed_corners(quad.corners, hypothesis.rotation);
  const auto refined = refine_corners_photometric(gray, tag_cells(family, hypothesis.id), start, opt.refine, {}, workspace);
  if (!refined) return std::nullopt;
  const auto H = tag_homography(*refined);
  if (!H) return std::nullopt;
  const auto again = read_payload_area(decode_image, *H, family.payload_width(), area);
  if (!again) return std::nullopt;
  const auto dec = family.decode(again->bits, corrected - opt.spare_bits);
  // The refined corners are in printed order: the code must come back unturned.
  if (!dec || dec->id != hypothesis.id || dec->rotation != 0) return std::nullopt;
  Detection d;
  d.family = family.name();
  d.id = dec->id;
  d.hamming = dec->hamming;
  d.rotation = hypothesis.rotation;
  d.decision_margin = again->margin;
  d.corners = *refined;
  d.homography = *H;
  d.center = apply_homography(*H, Eigen::Vector2d::Zero());
  d.observed_perimeter = quad.observed_perimeter;
  return d;
}

}  // namespace

std::vector<Detection> refit_to_nearest_codes(const ImageF& gray, const ImageF& decode_image,
                                              std::span<const Quad> quads, std::span<QuadOutcome> outcomes,
                                              std::span<const Detection> decoded,
                                              std::span<const TagFamily> families, int max_hamming,
                                              bool hamming_by_family, const PayloadAreaOptions& area,
                                              const CodeRefitOptions& opt, PhotometricWorkspace* workspace) {
  if (!opt.enabled) return {};
  return retry_undecoded_quads(
      quads, outcomes, decoded, families, opt.min_side_px, opt.max_side_px, opt.min_family_hamming, false,
      [&](std::size_t qi, const TagFamily& f) -> std::optional<Detection> {
        const auto& reading = outcomes[qi].bits[static_cast<std::size_t>(f.payload_width())];
        if (!reading) return std::nullopt;
        const int corrected = bits_corrected_for(f.min_hamming(), max_hamming, hamming_by_family);
        return try_family(gray, decode_image, quads[qi], *reading, f, corrected, area, opt, workspace);
      });
}

}  // namespace tagbench
