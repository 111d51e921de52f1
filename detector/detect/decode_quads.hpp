#pragma once
// Stage 6 of the detector (paper section IV): each candidate quad's payload read and decoded
// against every family.
//
// For each quad, in order: the border pre-filter (border_contrast_plausible, when
// payload.quick_reject; d = the widest payload of the families), the homography of the tag square,
// then one reading (read_payload) per payload width d among the families, shared by the families
// of that width, and every family's decode of its width's reading with at most max_hamming bits
// corrected. The family whose decode has the lowest Hamming distance wins. Tie-break: on equal
// Hamming distance the family that comes first in `families` (DetectorOptions::families' order)
// wins. A quad that no family decodes gives no detection.
//
// A detection's corners are the quad's corners re-ordered so that corners[0] is the printed
// top-left (quad corner `rotation`), its homography maps the tag square [-1,1]^2 in printed axes
// to the image, and its centre is the homography's image of (0, 0). Detections come in quad order.
#include <algorithm>
#include <optional>
#include <span>
#include <vector>

#include "codes/tag_family.hpp"
#include "detect/detector.hpp"
#include "detect/image.hpp"
#include "detect/payload_area.hpp"
#include "detect/payload_decode.hpp"
#include "detect/quad_search.hpp"
#include "detect/soft_decode.hpp"

namespace tagbench {

// `area`, if given, reads each payload over the cells' areas (read_payload_area, payload_area.hpp;
// its min_contrast replaced by payload.min_contrast) instead of at their centres (read_payload).
// `readings`, if given, receives every reading made (in quad order, then by payload width), with
// their sample points (for the paper's Fig. 4 pictures). `outcomes`, if given, receives one entry per
// quad, in order: what became of it (for explain_loss.hpp). `hamming_by_family`: each family corrects
// at most min(max_hamming, (h - 1) / 3) bits (DetectorOptions::hamming_by_family), else max_hamming.
// The best decode of one quad's readings (by_width[d]: the reading of payload width d, if any) over
// `families`, each correcting bits_corrected_for(...) bits: the lowest Hamming distance wins, the
// earlier family on ties. Fills best's family, id, hamming, rotation and decision_margin; false if no
// family decodes. Shared by decode_quads and the bent-tag second chance (bent_decode.hpp).
bool decode_readings(std::span<const TagFamily> families, std::span<const std::optional<PayloadReading>> by_width,
                     int max_hamming, bool hamming_by_family, Detection& best);

// The soft decode of one quad's readings (soft_decode.hpp) over `families`, for a quad no family
// decoded hard: the fewest hard-bit errors wins, the earlier family on ties. Fills best as
// decode_readings does (hamming: the best codeword's hard-bit distance); false if none is accepted.
bool soft_decode_readings(std::span<const TagFamily> families,
                          std::span<const std::optional<PayloadReading>> by_width, const SoftDecodeOptions& soft,
                          Detection& best);

// Records in `outcome` that its quad became the detection `d` (kDecoded, family, id, hamming, margin):
// decode_quads and the later second chances (bent_decode.hpp, code_refit.hpp) alike.
void mark_decoded(QuadOutcome& outcome, const Detection& d);

// The loop of the later second chances for quads read but not decoded (code_refit.hpp,
// defocus_read.hpp): every quad whose outcome is kNotDecoded, whose sides lie within [min_side_px,
// max_side_px] and whose centre lies inside no detection of `decoded` (nor, with skip_found, inside
// one this call found already) is offered to try_family(quad index, family) for every family of
// minimum distance at least min_family_hamming; of what they return, the fewest bits corrected wins
// (the earlier family on ties) and the quad's outcome is marked decoded. `quads` and `outcomes` are
// parallel; a size mismatch finds nothing. The new detections, in quad order.
template <class TryFamily>
std::vector<Detection> retry_undecoded_quads(std::span<const Quad> quads, std::span<QuadOutcome> outcomes,
                                             std::span<const Detection> decoded, std::span<const TagFamily> families,
                                             double min_side_px, double max_side_px, int min_family_hamming,
                                             bool skip_found, TryFamily&& try_family) {
  std::vector<Detection> found;
  if (outcomes.size() != quads.size()) return found;
  for (std::size_t qi = 0; qi < quads.size(); ++qi) {
    QuadOutcome& outcome = outcomes[qi];
    if (outcome.fate != QuadOutcome::Fate::kNotDecoded) continue;
    const auto [shortest, longest] = side_length_range(quads[qi].corners);
    if (!(shortest >= min_side_px) || !(longest <= max_side_px)) continue;
    const auto& c = quads[qi].corners;
    const Eigen::Vector2d centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
    const auto inside = [&](const Detection& d) { return inside_quad(d.corners, centre); };
    if (std::any_of(decoded.begin(), decoded.end(), inside) ||
        (skip_found && std::any_of(found.begin(), found.end(), inside)))
      continue;
    std::optional<Detection> best;
    for (const TagFamily& f : families) {
      if (f.min_hamming() < min_family_hamming) continue;
      std::optional<Detection> d = try_family(qi, f);
      if (d && (!best || d->hamming < best->hamming)) best = std::move(d);
    }
    if (!best) continue;
    mark_decoded(outcome, *best);
    found.push_back(std::move(*best));
  }
  return found;
}

// `soft`, if given and enabled, decodes soft the quads no family decoded hard (soft_decode_readings).
std::vector<Detection> decode_quads(const ImageF& decode_image, std::span<const Quad> quads,
                                    std::span<const TagFamily> families, int max_hamming,
                                    const PayloadOptions& payload, const PayloadAreaOptions* area = nullptr,
                                    std::vector<PayloadReading>* readings = nullptr,
                                    std::vector<QuadOutcome>* outcomes = nullptr, bool hamming_by_family = false,
                                    const SoftDecodeOptions* soft = nullptr);

}  // namespace tagbench
