// The files a sweep writes: rows and summaries as CSV, and the JSON sidecar.
#include <string>

#include "raytrace/sixdof.hpp"
#include "raytrace/sweep_detail.hpp"
#include "raytrace/sweeps.hpp"
#include "tools/format.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

const char* step_unit(const SweepFrame& f, Experiment e) {
  switch (e) {
    case Experiment::kAngle: return "deg";
    case Experiment::kDistance: return "m";
    case Experiment::kConditions: return condition_info(f.condition).unit;
    case Experiment::kSixdof: return "none";
  }
  return "";
}

// sixdof's columns after black_square_px: the Halton index and the camera.
constexpr const char* kSixdofHeader = ",halton_index,k1,k2,p1,p2,k3,defocus_sigma_px,noise_sigma,quantization_bits";

std::string sixdof_cells(const SweepFrame& f) {
  const CameraEffects c = f.effect.camera.value_or(CameraEffects{});
  std::string o = ",";
  o += std::to_string(f.sample);
  for (const double k : c.distortion) {
    o += ',';
    o += format_cell(k, "%.10g");
  }
  return o + "," + format_cell(c.defocus_sigma_px, "%.6f") + "," + format_cell(c.noise_sigma, "%.6f") + "," +
         std::to_string(c.quantization_bits);
}

std::string stats_cells(const SummaryRow& s) {
  const auto st = [](const ErrorStats& e) {
    return format_cell(e.median, "%.6g") + "," + format_cell(e.p10, "%.6g") + "," + format_cell(e.p90, "%.6g");
  };
  return std::to_string(s.frames) + "," + std::to_string(s.detected) + "," + format_cell(s.detection_rate, "%.6g") +
         "," + format_cell(s.rate_lo95, "%.6g") + "," + format_cell(s.rate_hi95, "%.6g") + "," +
         std::to_string(s.wrong_id_frames) + "," + format_cell(s.black_square_px_median, "%.4f") + "," +
         st(s.orientation_deg) + "," + st(s.distance_m) + "," + st(s.distance_percent) + "," + st(s.corner_rms_px) +
         "," + format_cell(s.ms_median, "%.4f") + lost_cells(s.lost);
}

constexpr const char* kStatsHeader =
    "frames,detected,detection_rate,rate_lo95,rate_hi95,"
    "wrong_id_frames,black_square_px_median,"
    "orientation_error_deg_median,orientation_error_deg_p10,orientation_error_deg_p90,"
    "distance_error_m_median,distance_error_m_p10,distance_error_m_p90,"
    "distance_error_percent_median,distance_error_percent_p10,distance_error_percent_p90,"
    "corner_rms_px_median,corner_rms_px_p10,corner_rms_px_p90,ms_median";

}  // namespace

std::string rows_csv(const SweepResult& r) {
  const SweepSettings& s = r.settings;
  const bool sixdof = s.experiment == Experiment::kSixdof;
  std::string o =
      "experiment,condition,step,step_unit,trial,seed,id,scene,family,tag_size_m,distance_m,phi_deg,tilt_axis_deg,"
      "roll_deg,image_x,image_y,black_square_px" +
      std::string(sixdof ? kSixdofHeader : "") +
      ",detector,detected_right_id,wrong_id,orientation_error_deg,"
      "distance_error_m,distance_error_percent,corner_rms_px,decision_margin,ms" +
      loss_header() + "\n";
  for (const SweepRow& row : r.rows) {
    const SweepFrame& f = r.frames[row.frame];
    o += std::string(experiment_name(s.experiment)) + "," + condition_name(f.condition) + "," +
         format_cell(f.step, "%.10g") + "," + step_unit(f, s.experiment) + "," + std::to_string(f.trial) + "," +
         std::to_string(f.seed) + "," + std::to_string(f.frame.id) + "," + scene_name(s.scene) + "," + csv_field(f.frame.family) +
         "," + format_cell(f.frame.tag_size, "%.10g") + "," + format_cell(f.frame.pose.t.norm(), "%.10g") + "," +
         format_cell(view_angle_deg(f.frame.pose), "%.6f") + "," + format_cell(f.view.tilt_axis_deg, "%.6f") + "," +
         format_cell(f.view.roll_deg, "%.6f") + "," + format_cell((sixdof ? f.image_position : f.view.pixel).x(), "%.4f") +
         "," + format_cell((sixdof ? f.image_position : f.view.pixel).y(), "%.4f") + "," +
         format_cell(f.truth.black_square_px, "%.4f") + (sixdof ? sixdof_cells(f) : std::string()) + "," + row.detector + "," + (row.detected_right_id ? "1" : "0") + "," + (row.wrong_id ? "1" : "0") + "," +
         format_cell(row.orientation_error_deg, "%.6g") + "," + format_cell(row.distance_error_m, "%.6g") + "," +
         format_cell(row.distance_error_percent, "%.6g") + "," + format_cell(row.corner_rms_px, "%.6g") + "," +
         format_cell(row.decision_margin, "%.6g") + "," + format_cell(row.ms, "%.4f") + loss_cells(row.loss) + "\n";
  }
  return o;
}

std::string summary_csv(const SweepResult& r, const std::vector<SummaryRow>& summary) {
  if (r.settings.experiment == Experiment::kSixdof) {
    std::string o = "experiment,variable,bin_lo,bin_hi,detector," + std::string(kStatsHeader) + lost_header() + "\n";
    for (const SummaryRow& s : summary)
      o += "sixdof," + s.variable + "," + format_cell(s.step, "%.10g") + "," + format_cell(s.bin_hi, "%.10g") + "," +
           s.detector + "," + stats_cells(s) + "\n";
    return o;
  }
  std::string o =
      "experiment,condition,step,step_unit,detector,frames,detected,detection_rate,rate_lo95,rate_hi95,"
      "wrong_id_frames,black_square_px_median,"
      "orientation_error_deg_median,orientation_error_deg_p10,orientation_error_deg_p90,"
      "distance_error_m_median,distance_error_m_p10,distance_error_m_p90,"
      "distance_error_percent_median,distance_error_percent_p10,distance_error_percent_p90,"
      "corner_rms_px_median,corner_rms_px_p10,corner_rms_px_p90,ms_median" +
      lost_header() + "\n";
  const auto st = [](const ErrorStats& e) {
    return format_cell(e.median, "%.6g") + "," + format_cell(e.p10, "%.6g") + "," + format_cell(e.p90, "%.6g");
  };
  for (const SummaryRow& s : summary) {
    SweepFrame probe;
    probe.condition = s.condition;
    o += std::string(experiment_name(r.settings.experiment)) + "," + condition_name(s.condition) + "," +
         format_cell(s.step, "%.10g") + "," + step_unit(probe, r.settings.experiment) + "," + s.detector + "," +
         std::to_string(s.frames) + "," + std::to_string(s.detected) + "," + format_cell(s.detection_rate, "%.6g") +
         "," + format_cell(s.rate_lo95, "%.6g") + "," + format_cell(s.rate_hi95, "%.6g") + "," +
         std::to_string(s.wrong_id_frames) + "," + format_cell(s.black_square_px_median, "%.4f") + "," +
         st(s.orientation_deg) + "," + st(s.distance_m) + "," + st(s.distance_percent) + "," + st(s.corner_rms_px) +
         "," + format_cell(s.ms_median, "%.4f");
    o += lost_cells(s.lost) + "\n";
  }
  return o;
}

std::string sidecar_json(const SweepResult& r) {
  const SweepSettings& s = r.settings;
  const CameraIntrinsics K = render_camera();
  std::string j = "{\n  \"tool\": \"tagbench raytrace\",\n";
  j += "  \"experiment\": " + json_string(experiment_name(s.experiment)) + ",\n";
  const bool sixdof = s.experiment == Experiment::kSixdof;
  const char* paper = s.experiment == Experiment::kAngle      ? "Fig. 9 (section VI-B)"
                      : s.experiment == Experiment::kDistance ? "Fig. 10 (section VI-B)"
                      : sixdof ? "beyond the paper: the FMAC protocol's 6-DoF sweep (arXiv 2601.07723)"
                               : "beyond the paper";
  j += "  \"paper\": " + json_string(paper) + ",\n";
  j += "  \"files\": {\"rows\": " + json_string(result_stem(s) + ".csv") +
       ", \"summary\": " + json_string(result_stem(s) + "_summary.csv") + "},\n";
  j += "  \"settings\": {\"scene\": " + json_string(scene_name(s.scene)) + ", \"family\": " + json_string(s.family) +
       ", \"tag_size_m\": " + json_number(*s.tag_size) + ", \"seed\": " + std::to_string(s.seed) +
       ", \"trials\": " + std::to_string(s.trials) + ",\n    \"steps\": " +
       (s.experiment == Experiment::kConditions || sixdof ? std::string("null") : json_numbers(s.steps)) +
       ", \"step_unit\": " +
       (s.experiment == Experiment::kAngle      ? json_string("deg")
        : s.experiment == Experiment::kDistance ? json_string("m")
                                                : std::string("null")) +
       ",\n    \"distance_m\": " + (s.distance ? json_number(*s.distance) : std::string("null")) +
       ", \"position_radius_px\": " + (sixdof ? std::string("null") : json_number(position_radius_px(s.experiment))) +
       ", \"phi_deg\": ";
  if (sixdof) j += "\"Halton, in [0, phi_max_deg]\"";
  else if (s.experiment == Experiment::kAngle) j += "\"the step\"";
  else if (s.experiment == Experiment::kDistance) j += "0";
  else
    j += "\"uniform in [0, " + format_cell(kConditionsMaxPhi, "%.10g") + "]\"";
  j += ",\n    \"detectors\": [";
  for (std::size_t i = 0; i < s.detectors.size(); ++i) j += (i ? ", " : "") + json_string(s.detectors[i]);
  if (!s.external.empty()) {  // only then: the built-in runs' sidecars keep their bytes
    j += "],\n    \"external\": [";
    for (std::size_t i = 0; i < s.external.size(); ++i)
      j += std::string(i ? ", " : "") + "{\"name\": " + json_string(s.external[i].name) +
           ", \"command\": " + json_string(s.external[i].command) +
           ", \"timeout_s\": " + json_number(s.external[i].timeout_seconds) + "}";
  }
  j += "],\n    \"random\": " +
       json_string(sixdof ? sixdof_description() : "per trial: splitmix64 seeded from (seed, experiment, trial) draws the id, the tilt axis and "
                   "the in-plane rotation (uniform in [0, 360) degrees), the image position (uniform in a disc of "
                   "position_radius_px about the principal point), and for conditions phi and the gradient's "
                   "direction; the same draws at every step");
  if (sixdof) j += ",\n    \"sixdof\": " + sixdof_settings_json(s);
  j += "},\n";
  j += "  \"camera\": {\"width\": " + std::to_string(kRenderWidth) + ", \"height\": " + std::to_string(kRenderHeight) +
       ", \"fx\": " + json_number(K.fx) + ", \"fy\": " + json_number(K.fy) + ", \"cx\": " + json_number(K.cx) +
       ", \"cy\": " + json_number(K.cy) +
       (sixdof ? ", \"distortion\": " + json_numbers({s.sixdof.distortion.begin(), s.sixdof.distortion.end()}) +
                     ", \"distortion_model\": \"OpenCV k1, k2, p1, p2, k3\""
               : std::string()) +
       ", \"renderer\": \"POV-Ray 3.7, +A0.1 +AM2 +R3, File_Gamma 1.0\", \"pixels\": \"centres at integer "
       "coordinates\"},\n";
  j += "  \"conditions\": [";
  if (s.experiment == Experiment::kConditions) {
    for (std::size_t i = 0; i < s.conditions.size(); ++i) {
      const auto& c = condition_info(s.conditions[i]);
      j += std::string(i ? "," : "") + "\n    {\"name\": " + json_string(c.name) + ", \"unit\": " + json_string(c.unit) +
           ", \"strengths\": " + json_numbers(c.strengths) + ",\n     \"description\": " + json_string(c.description) +
           "}";
    }
    j += "\n  ";
  }
  j += "],\n";
  j += "  \"measures\": " +
       json_string("detected_right_id: a detection with the frame's id; wrong_id: a detection with another id; "
                   "errors of the right-id detection nearest the truth: orientation = the angle of R_est^T R_true, "
                   "distance = | |t_est| - |t_true| | (m and % of |t_true|), corner RMS over the four corners (px); "
                   "ms: the detector's wall time on the frame, one thread; summaries: Wilson 95 % interval, "
                   "percentiles over the detected frames; loss_stage (detectors that can say, ours): for a frame not "
                   "detected with the right id, the stage where the tag was lost (no_cluster, no_segment, no_quad, "
                   "quad_rejected, misread, wrong_id, duplicate, below_margin; detect/explain_loss.hpp), found by "
                   "detecting again with a trace after timing, and loss_bits the bits of the tag's code read wrong "
                   "(misread, wrong_id); summaries: lost_STAGE, the missed frames per stage") +
       ",\n";
  j += "  \"frames\": " + std::to_string(r.frames.size()) + ", \"distinct_frames\": " +
       std::to_string(r.distinct_frames) + ", \"rendered\": " + std::to_string(r.rendered) +
       ", \"from_cache\": " + std::to_string(r.from_cache) + ", \"povray_runs\": " + std::to_string(r.povray_runs) +
       ",\n  \"render_seconds\": " + json_number(r.render_seconds) + ", \"detect_seconds\": " +
       json_number(r.detect_seconds) + ",\n";
  j += "  \"failed\": [";
  for (std::size_t i = 0; i < r.failed.size(); ++i) {
    const SweepFrame& f = r.frames[r.failed[i].frame];
    j += std::string(i ? "," : "") + "\n    {\"frame\": " + std::to_string(r.failed[i].frame) +
         ", \"condition\": " + json_string(condition_name(f.condition)) + ", \"step\": " + json_number(f.step) +
         ", \"trial\": " + std::to_string(f.trial) + ", \"error\": " + json_string(r.failed[i].error) + "}";
  }
  j += r.failed.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return j;
}

}  // namespace tagbench::bench
