#include "detect/decode_quads.hpp"

#include <algorithm>
#include <array>
#include <optional>

#include "codes/bits.hpp"
#include "detect/homography.hpp"

namespace tagbench {

namespace {

// The best family's decode of a quad's readings: `decode(family, reading)` gives the family's
// decoded tag or nothing; on equal Hamming distance the earlier family keeps the quad (">=": the
// header's tie-break).
template <typename Decode>
bool best_family_decode(std::span<const TagFamily> families,
                        std::span<const std::optional<PayloadReading>> by_width, Decode decode,
                        Detection& best) {
  bool have = false;
  for (const TagFamily& f : families) {
    const auto& reading = by_width[static_cast<std::size_t>(f.payload_width())];
    if (!reading) continue;
    const auto dec = decode(f, *reading);
    if (!dec || (have && dec->hamming >= best.hamming)) continue;
    have = true;
    best.family = f.name();
    best.id = dec->id;
    best.hamming = dec->hamming;
    best.rotation = dec->rotation;
    best.decision_margin = reading->margin;
  }
  return have;
}

// The second reading (SelfThresholdOptions, payload_area.hpp) of a quad the first decoded nothing
// from: one per payload width, each family correcting spare_bits fewer bits.
bool decode_self_threshold(const ImageF& img, const Eigen::Matrix3d& H, std::span<const TagFamily> families,
                           int max_hamming, bool hamming_by_family, const PayloadAreaOptions& area, Detection& best) {
  const SelfThresholdOptions& self = area.self_threshold;
  std::array<std::optional<PayloadReading>, kMaxPayloadWidth + 1> by_width;
  std::array<bool, kMaxPayloadWidth + 1> read{};
  for (const TagFamily& f : families) {
    const auto d = static_cast<std::size_t>(f.payload_width());
    if (read[d] || f.min_hamming() < self.min_family_hamming) continue;
    by_width[d] = read_payload_self_threshold(img, H, static_cast<int>(d), area);
    read[d] = true;
  }
  return best_family_decode(
      families, by_width,
      [&](const TagFamily& f, const PayloadReading& r) -> std::optional<DecodeResult> {
        const int corrected = bits_corrected_for(f.min_hamming(), max_hamming, hamming_by_family) - self.spare_bits;
        if (corrected < 0 || f.min_hamming() < self.min_family_hamming) return std::nullopt;
        return f.decode(r.bits, corrected);
      },
      best);
}

}  // namespace

bool decode_readings(std::span<const TagFamily> families, std::span<const std::optional<PayloadReading>> by_width,
                     int max_hamming, bool hamming_by_family, Detection& best) {
  return best_family_decode(
      families, by_width,
      [&](const TagFamily& f, const PayloadReading& r) {
        return f.decode(r.bits, bits_corrected_for(f.min_hamming(), max_hamming, hamming_by_family));
      },
      best);
}

bool soft_decode_readings(std::span<const TagFamily> families,
                          std::span<const std::optional<PayloadReading>> by_width, const SoftDecodeOptions& soft,
                          Detection& best) {
  return best_family_decode(
      families, by_width, [&](const TagFamily& f, const PayloadReading& r) { return soft_decode(f, r, soft); },
      best);
}

void mark_decoded(QuadOutcome& outcome, const Detection& d) {
  outcome.fate = QuadOutcome::Fate::kDecoded;
  outcome.family = d.family;
  outcome.id = d.id;
  outcome.hamming = d.hamming;
  outcome.decision_margin = d.decision_margin;
}

std::vector<Detection> decode_quads(const ImageF& decode_image, std::span<const Quad> quads,
                                    std::span<const TagFamily> families, int max_hamming,
                                    const PayloadOptions& payload, const PayloadAreaOptions* area,
                                    std::vector<PayloadReading>* readings,
                                    std::vector<QuadOutcome>* outcomes, bool hamming_by_family,
                                    const SoftDecodeOptions* soft) {
  std::vector<Detection> found;
  const int max_d = max_payload_width(families);
  std::optional<PayloadAreaOptions> area_opt;
  if (area) {
    area_opt = *area;
    area_opt->min_contrast = payload.min_contrast;
  }
  QuadOutcome scratch;
  for (const Quad& q : quads) {
    QuadOutcome& outcome = outcomes ? outcomes->emplace_back() : (scratch = QuadOutcome());
    outcome.fate = QuadOutcome::Fate::kBorderRejected;
    if (payload.quick_reject && !border_contrast_plausible(decode_image, q.corners, max_d, payload.min_contrast))
      continue;
    outcome.fate = QuadOutcome::Fate::kNoHomography;
    const auto H = tag_homography(q.corners);
    if (!H) continue;
    outcome.fate = QuadOutcome::Fate::kUnreadable;
    std::array<std::optional<PayloadReading>, kMaxPayloadWidth + 1> by_width;  // one reading per payload width d
    std::array<bool, kMaxPayloadWidth + 1> read{};
    for (const TagFamily& f : families) {
      const auto d = static_cast<std::size_t>(f.payload_width());
      if (read[d]) continue;
      by_width[d] = area_opt ? read_payload_area(decode_image, *H, static_cast<int>(d), *area_opt, readings != nullptr)
                             : read_payload(decode_image, *H, static_cast<int>(d), payload, readings != nullptr);
      read[d] = true;
      if (by_width[d]) {
        outcome.bits[d] = by_width[d]->bits;
        outcome.fate = QuadOutcome::Fate::kNotDecoded;
      }
    }
    Detection best;
    bool have = decode_readings(families, by_width, max_hamming, hamming_by_family, best);
    if (!have && area_opt && area_opt->self_threshold.enabled)
      have = decode_self_threshold(decode_image, *H, families, max_hamming, hamming_by_family, *area_opt, best);
    if (!have && soft && soft->enabled &&
        (soft->min_area_ratio <= 0 || quad_area_ratio(q.corners) >= soft->min_area_ratio) &&
        (soft->min_opposite_ratio <= 0 || quad_opposite_ratio(q.corners) >= soft->min_opposite_ratio))
      have = soft_decode_readings(families, by_width, *soft, best);
    if (readings)
      for (auto& r : by_width)
        if (r) readings->push_back(std::move(*r));
    if (!have) continue;
    mark_decoded(outcome, best);
    // The printed top-left corner is quad corner `rotation` (observed = rotate90^r(code)).
    best.corners = printed_corners(q.corners, best.rotation);
    best.homography = *tag_homography(best.corners);
    best.center = apply_homography(best.homography, Eigen::Vector2d::Zero());
    best.observed_perimeter = q.observed_perimeter;
    found.push_back(std::move(best));
  }
  return found;
}

}  // namespace tagbench
