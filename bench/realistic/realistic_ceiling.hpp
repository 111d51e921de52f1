#pragma once
// The payload reader's ceiling on the realistic set (issue 17): for every truth tag, could the default
// profile's decoding read it at all if the quad stages had found its TRUE corners? The tag's homography
// from the truth corners goes through decode_quads exactly as a candidate quad would (border pre-filter,
// the area reader or the point reader, the family's bits corrected), on the image the detector reads
// (the delivered 8-bit frame; DetectorOptions::decode_sigma 0). What the quad stages lose is then
// "detected by the ceiling, missed by the detector"; what the ceiling misses no quad finder can recover.
//
// The tag's contrast, in grey levels (0..255), is the white ring's model minus the black ring's at the
// tag's centre (PayloadReading::contrast of the area reader, payload_area.hpp), read through the truth
// homography; negative when the ring is darker than the border. Contrast bands group the tags by it.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "codes/tag_family.hpp"
#include "detect/detector.hpp"
#include "detect/image.hpp"
#include "realistic/realistic_run.hpp"

namespace tagbench::bench {

struct TruthReading {
  double contrast_levels = 0;             // white ring minus black ring, grey levels; NaN when unreadable
  bool area_decoded = false;              // decode_quads with the area reader gave the tag's own id
  bool point_decoded = false;             // ... with the point reader
  bool area_soft_decoded = false;         // ... with the area reader, then (where no family decoded it
                                          // hard) the soft decoder (soft_decode.hpp, opt.soft_decode, enabled)
  int area_bits_wrong = -1, point_bits_wrong = -1;  // bits of the tag's code read wrong (best rotation); -1: no reading
};

// Reads `tag` (family `family`) of `gray` through its truth corners with `opt`'s decoding settings
// (max_hamming, hamming_by_family, payload, payload_area). `family` must be tag.family.
TruthReading read_at_truth(const ImageF& gray, const RealisticTag& tag, const TagFamily& family,
                           const DetectorOptions& opt);

// Contrast bands (grey levels): [-inf,10) [10,15) [15,20) [20,30) [30,50) [50,inf).
const std::vector<std::string>& contrast_band_names();
const std::string& contrast_band_of(double contrast_levels);

// All frames' truth readings, frame-major then tag (RealisticResult's frames and tags).
struct CeilingResult {
  std::vector<std::vector<TruthReading>> by_frame;
};

struct CeilingSummaryRow {
  std::string bin, band;               // size bin (size_bins()) or "all"; contrast band or "all"
  int tags = 0, area = 0, area_soft = 0, point = 0, either = 0;  // either: area (then soft) or point
  std::vector<int> detected;           // per RealisticResult::settings.detectors
};
// Rows for every used (size bin, band) pair, each size bin with band "all", and ("all", "all").
std::vector<CeilingSummaryRow> summarize_ceiling(const RealisticResult& result, const CeilingResult& ceiling);

// realistic_ceiling.csv: a row per tag (frame, tag, id, black_square_px, size_bin, contrast_levels,
// contrast_band, area_decoded, area_bits_wrong, area_soft_decoded, point_decoded, point_bits_wrong, then detected_<name> and
// loss_<name> per detector). realistic_ceiling_summary.csv: the summary rows.
std::string ceiling_rows_csv(const RealisticResult& result, const CeilingResult& ceiling);
std::string ceiling_summary_csv(const RealisticResult& result, const std::vector<CeilingSummaryRow>& rows);

}  // namespace tagbench::bench
