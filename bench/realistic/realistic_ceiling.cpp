// The payload reader's ceiling on the realistic set (realistic_ceiling.hpp).
#include "realistic/realistic_ceiling.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "codes/bits.hpp"
#include "detect/decode_quads.hpp"
#include "detect/homography.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

namespace {

// Decodes the one quad `corners` with the area reader (area != nullptr) or the point reader.
// Returns (decoded as the tag's own id, bits of its code read wrong or -1).
std::pair<bool, int> decode_one(const ImageF& gray, const Corners& corners, const TagFamily& family, int id,
                                const DetectorOptions& opt, const PayloadAreaOptions* area,
                                const SoftDecodeOptions* soft = nullptr) {
  Quad q;
  q.corners = corners;
  std::vector<QuadOutcome> outcomes;
  const std::vector<Detection> found = decode_quads(gray, std::span(&q, 1), std::span(&family, 1), opt.max_hamming,
                                                    opt.payload, area, nullptr, &outcomes, opt.hamming_by_family, soft);
  const auto d = static_cast<std::size_t>(family.payload_width());
  int wrong = -1;
  if (!outcomes.empty() && outcomes[0].bits[d])
    wrong = hamming_with_rotations(*outcomes[0].bits[d], family.codes()[static_cast<std::size_t>(id)],
                                   family.payload_width());
  const bool ok = found.size() == 1 && found[0].id == id;
  return {ok, wrong};
}


}  // namespace

TruthReading read_at_truth(const ImageF& gray, const RealisticTag& tag, const TagFamily& family,
                           const DetectorOptions& opt) {
  TruthReading r;
  r.contrast_levels = std::numeric_limits<double>::quiet_NaN();
  if (const auto H = tag_homography(tag.corners)) {
    PayloadAreaOptions any = opt.payload_area;
    any.min_contrast = -1;  // measure the contrast whatever it is
    if (const auto reading = read_payload_area(gray, *H, family.payload_width(), any))
      r.contrast_levels = reading->contrast * 255;
  }
  std::tie(r.area_decoded, r.area_bits_wrong) = decode_one(gray, tag.corners, family, tag.id, opt, &opt.payload_area);
  std::tie(r.point_decoded, r.point_bits_wrong) = decode_one(gray, tag.corners, family, tag.id, opt, nullptr);
  SoftDecodeOptions soft = opt.soft_decode;
  soft.enabled = true;
  r.area_soft_decoded =
      r.area_decoded || decode_one(gray, tag.corners, family, tag.id, opt, &opt.payload_area, &soft).first;
  return r;
}

const std::vector<std::string>& contrast_band_names() {
  static const std::vector<std::string> names = {"<10", "10-15", "15-20", "20-30", "30-50", ">=50"};
  return names;
}

const std::string& contrast_band_of(double c) {
  const auto& n = contrast_band_names();
  static const std::array<double, 5> upper = {10, 15, 20, 30, 50};
  for (std::size_t i = 0; i < upper.size(); ++i)
    if (!(c >= upper[i])) return n[i];  // NaN (unreadable) counts as the lowest band
  return n.back();
}

std::vector<CeilingSummaryRow> summarize_ceiling(const RealisticResult& r, const CeilingResult& c) {
  const std::size_t nd = r.settings.detectors.size();
  std::map<std::pair<std::string, std::string>, CeilingSummaryRow> acc;
  for (const TagScore& sc : r.scores) {
    const RealisticTag& t = r.frames[sc.frame].tags[sc.tag];
    const TruthReading& tr = c.by_frame.at(sc.frame).at(sc.tag);
    const std::string& bin = size_bin_of(t.black_square_px).name;
    const std::string& band = contrast_band_of(tr.contrast_levels);
    std::size_t det = 0;
    while (det < nd && r.settings.detectors[det] != sc.detector) ++det;
    const bool first = det == 0;  // count the tag once (its first detector's row)
    for (const auto& key : {std::pair{bin, band}, std::pair{bin, std::string("all")},
                            std::pair{std::string("all"), std::string("all")}}) {
      CeilingSummaryRow& row = acc[key];
      if (row.detected.empty()) row.detected.assign(nd, 0), row.bin = key.first, row.band = key.second;
      if (first) {
        ++row.tags;
        row.area += tr.area_decoded;
        row.area_soft += tr.area_soft_decoded;
        row.point += tr.point_decoded;
        row.either += tr.area_soft_decoded || tr.point_decoded;
      }
      if (sc.detected && det < nd) ++row.detected[det];
    }
  }
  std::vector<CeilingSummaryRow> out;
  std::vector<std::string> bins;
  for (const auto& b : size_bins()) bins.push_back(b.name);
  bins.push_back("all");
  std::vector<std::string> bands = contrast_band_names();
  bands.push_back("all");
  for (const auto& b : bins)
    for (const auto& k : bands)
      if (const auto it = acc.find({b, k}); it != acc.end()) out.push_back(it->second);
  return out;
}

std::string ceiling_rows_csv(const RealisticResult& r, const CeilingResult& c) {
  const auto& dets = r.settings.detectors;
  std::string o =
      "set,seed,family,frame,tag,id,black_square_px,size_bin,contrast_levels,contrast_band,area_decoded,"
      "area_bits_wrong,area_soft_decoded,point_decoded,point_bits_wrong";
  for (const auto& d : dets) o += ",detected_" + d + ",loss_" + d;
  o += "\n";
  const std::string pre = "realistic," + std::to_string(r.settings.set.seed) + "," + r.settings.set.family + ",";
  // r.scores is frame, tag, then detector order: one output row per tag.
  for (std::size_t i = 0; i < r.scores.size(); i += dets.size()) {
    const TagScore& sc = r.scores[i];
    const RealisticTag& t = r.frames[sc.frame].tags[sc.tag];
    const TruthReading& tr = c.by_frame.at(sc.frame).at(sc.tag);
    o += pre + std::to_string(r.frames[sc.frame].index) + "," + std::to_string(sc.tag) + "," + std::to_string(t.id) +
         "," + format_cell(t.black_square_px, "%.4f") + "," + size_bin_of(t.black_square_px).name + "," +
         format_cell(tr.contrast_levels, "%.2f") + "," + contrast_band_of(tr.contrast_levels) + "," +
         (tr.area_decoded ? "1" : "0") + "," + std::to_string(tr.area_bits_wrong) + "," +
         (tr.area_soft_decoded ? "1" : "0") + "," +
         (tr.point_decoded ? "1" : "0") + "," + std::to_string(tr.point_bits_wrong);
    for (std::size_t d = 0; d < dets.size(); ++d) {
      const TagScore& s = r.scores[i + d];
      o += std::string(",") + (s.detected ? "1" : "0") + "," + (s.loss ? loss_stage_name(s.loss->stage) : "");
    }
    o += "\n";
  }
  return o;
}

std::string ceiling_summary_csv(const RealisticResult& r, const std::vector<CeilingSummaryRow>& rows) {
  const auto& dets = r.settings.detectors;
  std::string o = "set,seed,family,frames,size_bin,contrast_band,tags,ceiling_area,ceiling_area_soft,ceiling_point,ceiling_either";
  for (const auto& d : dets) o += ",detected_" + d;
  o += "\n";
  const std::string pre = "realistic," + std::to_string(r.settings.set.seed) + "," + r.settings.set.family + "," +
                          std::to_string(r.frames.size()) + ",";
  for (const auto& row : rows) {
    o += pre + row.bin + "," + row.band + "," + std::to_string(row.tags) + "," + std::to_string(row.area) + "," + std::to_string(row.area_soft) + "," +
         std::to_string(row.point) + "," + std::to_string(row.either);
    for (const int n : row.detected) {
      o += ',';
      o += std::to_string(n);
    }
    o += "\n";
  }
  return o;
}

}  // namespace tagbench::bench
