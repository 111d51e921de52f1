// The realistic set's result files (realistic_run.hpp): every CSV has a header row and carries the
// set's settings in its columns (set, seed, family); the JSON sidecar has all of them.
#include <cmath>

#include "realistic/realistic_run.hpp"
#include "tools/json.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

namespace {

// A CSV number: empty when not finite (tools/format.hpp).
std::string num(double v, const char* format = "%.10g") { return format_cell(v, format); }

std::string range_json(const Range& r) { return std::string("[") + json_number(r.lo) + ", " + json_number(r.hi) + "]"; }

std::string settings_prefix(const RealisticResult& r) {
  return "realistic," + std::to_string(r.settings.set.seed) + "," + r.settings.set.family + ",";
}

}  // namespace

std::string realistic_rows_csv(const RealisticResult& r) {
  std::string o =
      "set,seed,family,frame,frame_seed,blur_sigma_px,motion_blur_px,full_well_e,read_noise_e,jpeg_quality,exposure,"
      "shadow,tag,id,black_square_px,size_bin,mean_edge_px,tilt_deg,roll_deg,center_x,center_y,ink,paper,light,"
      "detector,detected,wrong_id,corner_rms_px,decision_margin,ms" +
      loss_header() + "\n";
  const std::string pre = settings_prefix(r);
  for (const TagScore& sc : r.scores) {
    const RealisticFrameInfo& f = r.frames[sc.frame];
    const CameraDegradation& d = f.degradation;
    const RealisticTag& t = f.tags[sc.tag];
    const Eigen::Vector2d c = (t.corners[0] + t.corners[1] + t.corners[2] + t.corners[3]) / 4;
    o += pre + std::to_string(f.index) + "," + std::to_string(f.frame_seed) + "," + num(d.blur_sigma_px, "%.4f") + "," +
         num(d.motion_blur_px, "%.4f") + "," + num(d.full_well_e, "%.1f") + "," + num(d.read_noise_e, "%.3f") + "," +
         std::to_string(d.jpeg_quality) + "," + num(d.exposure, "%.4f") + "," + (d.shadow ? "1" : "0") + "," +
         std::to_string(sc.tag) + "," + std::to_string(t.id) + "," + num(t.black_square_px, "%.4f") + "," +
         size_bin_of(t.black_square_px).name + "," + num(t.mean_edge_px, "%.4f") + "," + num(t.tilt_deg, "%.4f") + "," +
         num(t.roll_deg, "%.4f") + "," + num(c.x(), "%.4f") + "," + num(c.y(), "%.4f") + "," + num(t.ink, "%.4f") +
         "," + num(t.paper, "%.4f") + "," + num(t.light, "%.4f") + "," + sc.detector + "," +
         (sc.detected ? "1" : "0") + "," + (sc.wrong_id ? "1" : "0") + "," + num(sc.corner_rms_px, "%.6g") + "," +
         num(sc.decision_margin, "%.6g") + "," + num(sc.ms, "%.4f") + loss_cells(sc.loss) + "\n";
  }
  return o;
}

std::string realistic_false_csv(const RealisticResult& r) {
  std::string o = "set,seed,family,frame,detector,detected_family,id,size_px,size_bin,center_x,center_y,at_tag\n";
  const std::string pre = settings_prefix(r);
  for (const RealisticFalseDetection& fd : r.false_detections)
    o += pre + std::to_string(r.frames[fd.frame].index) + "," + fd.detector + "," + fd.family + "," +
         std::to_string(fd.id) + "," + num(fd.size_px, "%.4f") + "," + size_bin_of(fd.size_px).name + "," +
         num(fd.centre.x(), "%.4f") + "," + num(fd.centre.y(), "%.4f") + "," + std::to_string(fd.at_tag) + "\n";
  return o;
}

std::string realistic_summary_csv(const RealisticResult& r, const std::vector<RealisticSummaryRow>& summary) {
  std::string o =
      "set,seed,family,frames,size_bin,bin_lo_px,bin_hi_px,detector,tags,detected,detection_rate,rate_lo95,rate_hi95,"
      "wrong_id_tags,false_detections,corner_rms_px_median,corner_rms_px_p90" +
      lost_header() + "\n";
  const std::string pre = settings_prefix(r) + std::to_string(r.frames.size()) + ",";
  for (const auto& s : summary)
    o += pre + s.bin + "," + num(s.bin_lo) + "," + num(s.bin_hi) + "," + s.detector + "," + std::to_string(s.tags) +
         "," + std::to_string(s.detected) + "," + num(s.rate, "%.6g") + "," + num(s.rate_lo95, "%.6g") + "," +
         num(s.rate_hi95, "%.6g") + "," + std::to_string(s.wrong_id_tags) + "," + std::to_string(s.false_detections) +
         "," + num(s.corner_rms_px_median, "%.6g") + "," + num(s.corner_rms_px_p90, "%.6g") + lost_cells(s.lost) + "\n";
  return o;
}

std::string realistic_sidecar_json(const RealisticResult& r, const std::vector<RealisticSummaryRow>& summary) {
  const RealisticSettings& s = r.settings.set;
  std::size_t tags = 0;
  for (const auto& f : r.frames) tags += f.tags.size();
  std::string j = "{\n  \"tool\": \"tagbench realistic\",\n";
  j += "  \"files\": {\"rows\": \"realistic.csv\", \"false_detections\": \"realistic_false.csv\", \"summary\": "
       "\"realistic_summary.csv\", \"plot\": \"realistic.png\"},\n";
  j += "  \"settings\": {\"seed\": " + std::to_string(s.seed) + ", \"family\": " + json_string(s.family) +
       ", \"frames\": " + std::to_string(r.settings.frames) + ", \"width\": " + std::to_string(s.width) +
       ", \"height\": " + std::to_string(s.height) + ", \"focal_px\": " + json_number(s.focal_px) +
       ",\n    \"tags_per_frame\": [" + std::to_string(s.min_tags) + ", " + std::to_string(s.max_tags) +
       "], \"black_square_px\": " + range_json(s.black_square_px) + ", \"max_tilt_deg\": " +
       json_number(s.max_tilt_deg) + ", \"tag_size_m\": " + json_number(s.tag_size_m) + ", \"supersample\": " +
       std::to_string(s.supersample) + ",\n    \"degrade\": " + (s.degrade ? "true" : "false") +
       ", \"blur_sigma_px\": " + range_json(s.blur_sigma_px) +
       (s.disk_defocus ? ", \"disk_defocus\": true" : "") +  // only when on: the set's files as before
       ", \"motion_blur_px\": " + range_json(s.motion_blur_px) + ", \"full_well_e\": " + range_json(s.full_well_e) + ", \"read_noise_e\": " +
       range_json(s.read_noise_e) + ", \"jpeg_quality\": " + range_json(s.jpeg_quality) + ", \"gamma\": " +
       json_number(s.gamma) + ",\n    \"exposure\": " + range_json(s.exposure) + ", \"ink_reflectance\": " +
       range_json(s.ink_reflectance) + ", \"paper_reflectance\": " + range_json(s.paper_reflectance) +
       ", \"face_light\": " + range_json(s.face_light) + ", \"unevenness\": " + json_number(s.unevenness) +
       ", \"shadow_probability\": " + json_number(s.shadow_probability) + ",\n    \"detectors\": [";
  for (std::size_t i = 0; i < r.settings.detectors.size(); ++i) j += (i ? ", " : "") + json_string(r.settings.detectors[i]);
  j += "],\n    \"random\": " +
       json_string("frame i's draws come from splitmix64 seeded by (seed, i) (frame_seed): tag count, sizes (sqrt of "
                   "the black square's area, uniform), tilts (uniform in [0, max_tilt_deg]), axes, rolls, positions, "
                   "ids (distinct), reflectances; the ground; the light; the camera's per-frame values") +
       "},\n";
  j += "  \"how\": " +
       json_string("pinhole camera, principal point at the image centre (pixel centres at integers); tags rendered "
                   "projectively with a random surround plate, on procedural cluttered ground, at supersample x "
                   "supersample samples per pixel, box-averaged; light: a smooth variation and maybe a hard shadow; "
                   "camera: Gaussian defocus, line motion blur, shot noise (full well) and read noise, gamma, 8-bit, "
                   "JPEG (OpenCV imencode), detectors see the decoded JPEG") +
       ",\n";
  j += "  \"measures\": " +
       json_string("detected: a detection of the tag's family and id with corner RMS <= max(2 px, 0.2 x black "
                   "square); every other detection is false (realistic_false.csv), a wrong id when its centre is in "
                   "a tag's black square; size bins by sqrt of the black square's area (false detections: of their "
                   "quad); rates with Wilson 95 % intervals; corner RMS percentiles over detected tags; ms: the "
                   "detector's wall time on the whole frame, one thread; loss_stage and loss_bits (detectors that can say, "
                   "ours): where a missed tag was lost and the bits of its code read wrong (detect/explain_loss.hpp), "
                   "found by detecting again with a trace after timing; summary lost_STAGE: missed tags per stage") +
       ",\n";
  j += "  \"frames\": " + std::to_string(r.frames.size()) + ", \"tags\": " + std::to_string(tags) +
       ", \"false_detections\": " + std::to_string(r.false_detections.size()) + ",\n  \"generate_seconds\": " +
       json_number(r.generate_seconds) + ", \"detect_seconds\": " + json_number(r.detect_seconds) + ",\n";
  j += "  \"summary\": [";
  for (std::size_t i = 0; i < summary.size(); ++i) {
    const auto& s2 = summary[i];
    j += std::string(i ? "," : "") + "\n    {\"size_bin\": " + json_string(s2.bin) + ", \"detector\": " +
         json_string(s2.detector) + ", \"tags\": " + std::to_string(s2.tags) + ", \"detected\": " +
         std::to_string(s2.detected) + ", \"rate\": " + json_number(s2.rate) + ", \"rate_ci95\": [" +
         json_number(s2.rate_lo95) + ", " + json_number(s2.rate_hi95) + "], \"false_detections\": " +
         std::to_string(s2.false_detections) + "}";
  }
  j += "\n  ]\n}\n";
  return j;
}

}  // namespace tagbench::bench
