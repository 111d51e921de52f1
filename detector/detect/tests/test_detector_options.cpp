// DetectorOptions::validate: every numeric field, one bad value each (the message must name the
// field and give the value), the boundaries that must pass, and the constructor calling it.
#include <gtest/gtest.h>

#include <fstream>

#include <filesystem>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "codes/families.hpp"
#include "detect/detector.hpp"

namespace test_detector_options {

using namespace tagbench;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Case {
  std::string field;  // as validate() spells it
  std::function<void(DetectorOptions&)> set;
  std::string value;  // how the message prints the bad value
};

DetectorOptions with_camera() {
  DetectorOptions o;
  o.camera = CameraIntrinsics{500, 500, 320, 240};
  o.tag_size = 0.1;
  return o;
}

std::string message(const DetectorOptions& o) {
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(DetectorOptions, EveryFieldIsChecked) {
  // One entry per numeric field of DetectorOptions and its nested options (a field missing from
  // validate() leaves its case accepted and fails here).
  const std::vector<Case> cases = {
      {"max_hamming", [](DetectorOptions& o) { o.max_hamming = -1; }, "-1"},
      {"max_hamming", [](DetectorOptions& o) { o.hamming_by_family = false, o.max_hamming = 11; }, "11"},  // 36h11: h - 1 = 10
      {"max_hamming", [](DetectorOptions& o) { o.max_hamming = 17; }, "17"},  // by family: a cap, 0..16
      {"min_decision_margin", [](DetectorOptions& o) { o.min_decision_margin = 1.5; }, "1.5"},
      {"min_decision_margin", [](DetectorOptions& o) { o.min_decision_margin = kNaN; }, "nan"},
      {"seg_sigma", [](DetectorOptions& o) { o.seg_sigma = -0.1; }, "-0.1"},
      {"seg_sigma", [](DetectorOptions& o) { o.seg_sigma = kInf; }, "inf"},
      {"decode_sigma", [](DetectorOptions& o) { o.decode_sigma = kNaN; }, "nan"},
      {"segmentation.min_mag", [](DetectorOptions& o) { o.segmentation.min_mag = -1; }, "-1"},
      {"segmentation.max_edge_cost", [](DetectorOptions& o) { o.segmentation.max_edge_cost = 0; }, "0"},
      {"segmentation.max_edge_cost", [](DetectorOptions& o) { o.segmentation.max_edge_cost = 4; }, "4"},
      {"segmentation.weight_scale", [](DetectorOptions& o) { o.segmentation.weight_scale = 0; }, "0"},
      {"segmentation.weight_scale", [](DetectorOptions& o) { o.segmentation.weight_scale = kMaxWeightScale + 1; },
       std::to_string(kMaxWeightScale + 1)},
      {"segmentation.k_theta", [](DetectorOptions& o) { o.segmentation.k_theta = -1; }, "-1"},
      {"segmentation.k_mag", [](DetectorOptions& o) { o.segmentation.k_mag = kNaN; }, "nan"},
      {"segmentation.min_cluster_size", [](DetectorOptions& o) { o.segmentation.min_cluster_size = 0; }, "0"},
      {"line_fit.min_length", [](DetectorOptions& o) { o.line_fit.min_length = -4; }, "-4"},
      {"quad_search.close_enough",
       [](DetectorOptions& o) { o.quad_search.close_enough = static_cast<CloseEnoughRule>(7); }, "7"},
      {"quad_search.min_tag_size", [](DetectorOptions& o) { o.quad_search.min_tag_size = 0; }, "0"},
      {"quad_search.max_aspect", [](DetectorOptions& o) { o.quad_search.max_aspect = 0.5; }, "0.5"},
      {"quad_search.winding_min", [](DetectorOptions& o) { o.quad_search.winding_min = -kInf; }, "-inf"},
      {"quad_search.winding_max", [](DetectorOptions& o) { o.quad_search.winding_max = -8; }, "-8"},
      {"quad_search.grid_cell", [](DetectorOptions& o) { o.quad_search.grid_cell = 0; }, "0"},
      {"quad_search.grid_cell", [](DetectorOptions& o) { o.quad_search.grid_cell = kNaN; }, "nan"},
      {"quad_search.max_quads", [](DetectorOptions& o) { o.quad_search.max_quads = 0; }, "0"},
      {"dark_outlines.min_size_px", [](DetectorOptions& o) { o.dark_outlines.min_size_px = -1; }, "-1"},
      {"dark_outlines.max_size_px", [](DetectorOptions& o) { o.dark_outlines.max_size_px = 0; }, "0"},
      {"dark_outlines.min_groups", [](DetectorOptions& o) { o.dark_outlines.min_groups = 1; }, "1"},
      {"dark_outlines.max_groups", [](DetectorOptions& o) { o.dark_outlines.max_groups = 1; }, "1"},
      {"dark_outlines.slack_sides", [](DetectorOptions& o) { o.dark_outlines.slack_sides = 5; }, "5"},
      {"dark_outlines.pair_margin_px", [](DetectorOptions& o) { o.dark_outlines.pair_margin_px = -0.5; }, "-0.5"},
      {"dark_outlines.pair_min_points", [](DetectorOptions& o) { o.dark_outlines.pair_min_points = -1; }, "-1"},
      {"dark_outlines.pair_min_share", [](DetectorOptions& o) { o.dark_outlines.pair_min_share = 1.5; }, "1.5"},
      {"payload_area.self_threshold.max_light_black_ring",
       [](DetectorOptions& o) { o.payload_area.self_threshold.max_light_black_ring = 1.5; }, "1.5"},
      {"payload_area.self_threshold.spare_bits", [](DetectorOptions& o) { o.payload_area.self_threshold.spare_bits = -1; },
       "-1"},
      {"payload_area.self_threshold.min_family_hamming",
       [](DetectorOptions& o) { o.payload_area.self_threshold.min_family_hamming = -2; }, "-2"},
      {"payload.min_contrast", [](DetectorOptions& o) { o.payload.min_contrast = -0.01; }, "-0.01"},
      {"quad_finder", [](DetectorOptions& o) { o.quad_finder = static_cast<QuadFinderKind>(5); }, "5"},
      {"photometric.iterations", [](DetectorOptions& o) { o.photometric.iterations = 0; }, "0"},
      {"photometric.min_pixels", [](DetectorOptions& o) { o.photometric.min_pixels = 0; }, "0"},
      {"photometric.max_pixels", [](DetectorOptions& o) { o.photometric.max_pixels = 3; }, "3"},
      {"photometric.margin_cells", [](DetectorOptions& o) { o.photometric.margin_cells = 1; }, "1"},
      {"photometric.band_px", [](DetectorOptions& o) { o.photometric.band_px = 0; }, "0"},
      {"photometric.initial_blur_px", [](DetectorOptions& o) { o.photometric.initial_blur_px = kNaN; }, "nan"},
      {"photometric.max_corner_shift_px", [](DetectorOptions& o) { o.photometric.max_corner_shift_px = -1; }, "-1"},
      {"photometric.min_black_square_px", [](DetectorOptions& o) { o.photometric.min_black_square_px = kInf; }, "inf"},
      {"photometric.huber", [](DetectorOptions& o) { o.photometric.huber = -0.5; }, "-0.5"},
      {"photometric.max_blur_cells", [](DetectorOptions& o) { o.photometric.max_blur_cells = 0; }, "0"},
      {"photometric.pixels_per_side_px", [](DetectorOptions& o) { o.photometric.pixels_per_side_px = kNaN; }, "nan"},
      {"photometric.min_contrast", [](DetectorOptions& o) { o.photometric.min_contrast = 1.5; }, "1.5"},
      {"photometric_guard.max_kink_px", [](DetectorOptions& o) { o.photometric_guard.max_kink_px = -1; }, "-1"},
      {"photometric_guard.min_kink_significance", [](DetectorOptions& o) { o.photometric_guard.min_kink_significance = kNaN; }, "nan"},
      {"photometric_guard.min_side_px", [](DetectorOptions& o) { o.photometric_guard.min_side_px = kInf; }, "inf"},
      {"photometric_guard.max_blur_px", [](DetectorOptions& o) { o.photometric_guard.max_blur_px = -0.5; }, "-0.5"},
      {"photometric_guard.kink.samples", [](DetectorOptions& o) { o.photometric_guard.kink.samples = 3; }, "3"},
      {"bent.min_kink_px", [](DetectorOptions& o) { o.bent.min_kink_px = kNaN; }, "nan"},
      {"bent.precheck_samples", [](DetectorOptions& o) { o.bent.precheck_samples = 2; }, "2"},
      {"bent.precheck_fraction", [](DetectorOptions& o) { o.bent.precheck_fraction = 1.5; }, "1.5"},
      {"bent.min_side_px", [](DetectorOptions& o) { o.bent.min_side_px = -1; }, "-1"},
      {"bent.kink.samples", [](DetectorOptions& o) { o.bent.kink.samples = 1000; }, "1000"},
      {"bent.kink.end_margin", [](DetectorOptions& o) { o.bent.kink.end_margin = 0.5; }, "0.5"},
      {"bent.kink.range_cells", [](DetectorOptions& o) { o.bent.kink.range_cells = 0; }, "0"},
      {"bent.kink.min_range_px", [](DetectorOptions& o) { o.bent.kink.min_range_px = -1; }, "-1"},
      {"bent.kink.step_px", [](DetectorOptions& o) { o.bent.kink.step_px = 0; }, "0"},
      {"bent.kink.derivative_half_px", [](DetectorOptions& o) { o.bent.kink.derivative_half_px = kInf; }, "inf"},
      {"bent.kink.max_fold_offset", [](DetectorOptions& o) { o.bent.kink.max_fold_offset = 1; }, "1"},
      {"bent.kink.cells_across", [](DetectorOptions& o) { o.bent.kink.cells_across = 0; }, "0"},
      {"occlusion.sample_spacing_px", [](DetectorOptions& o) { o.occlusion.sample_spacing_px = 0; }, "0"},
      {"occlusion.end_margin_px", [](DetectorOptions& o) { o.occlusion.end_margin_px = -1; }, "-1"},
      {"occlusion.agree_fraction", [](DetectorOptions& o) { o.occlusion.agree_fraction = 1.5; }, "1.5"},
      {"occlusion.max_disagree", [](DetectorOptions& o) { o.occlusion.max_disagree = kNaN; }, "nan"},
      {"occlusion.erode_samples", [](DetectorOptions& o) { o.occlusion.erode_samples = -1; }, "-1"},
      {"occlusion.min_visible", [](DetectorOptions& o) { o.occlusion.min_visible = 2; }, "2"},
      {"occlusion.min_median_contrast", [](DetectorOptions& o) { o.occlusion.min_median_contrast = -0.5; }, "-0.5"},
      {"occlusion.max_corner_shift_cells", [](DetectorOptions& o) { o.occlusion.max_corner_shift_cells = 0; }, "0"},
      {"occlusion.iterations", [](DetectorOptions& o) { o.occlusion.iterations = 0; }, "0"},
      {"occlusion.min_cell_px", [](DetectorOptions& o) { o.occlusion.min_cell_px = kInf; }, "inf"},
      {"threshold_quads.fit.occluded.min_radial_cos",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_radial_cos = 2; }, "2"},
      {"threshold_quads.fit.occluded.min_group_points",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_group_points = 3; }, "3"},
      {"threshold_quads.fit.occluded.split_tolerance_px",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.split_tolerance_px = 0; }, "0"},
      {"threshold_quads.fit.occluded.merge_angle_deg",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.merge_angle_deg = 95; }, "95"},
      {"threshold_quads.fit.occluded.max_line_mse",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.max_line_mse = kNaN; }, "nan"},
      {"threshold_quads.fit.occluded.merge_distance_px",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.merge_distance_px = -1; }, "-1"},
      {"threshold_quads.fit.occluded.inside_tolerance_px",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.inside_tolerance_px = kInf; }, "inf"},
      {"threshold_quads.fit.occluded.max_lines", [](DetectorOptions& o) { o.threshold_quads.fit.occluded.max_lines = 17; }, "17"},
      {"threshold_quads.fit.occluded.max_runs", [](DetectorOptions& o) { o.threshold_quads.fit.occluded.max_runs = 3; }, "3"},
      {"threshold_quads.fit.occluded.min_side_fraction",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_side_fraction = 1.5; }, "1.5"},
      {"threshold_quads.fit.occluded.min_total_coverage",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_total_coverage = 5; }, "5"},
      {"threshold_quads.fit.occluded.min_on_lines",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_on_lines = -0.1; }, "-0.1"},
      {"threshold_quads.fit.occluded.max_inside_outliers",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.max_inside_outliers = kNaN; }, "nan"},
      {"threshold_quads.fit.occluded.min_three_side_coverage",
       [](DetectorOptions& o) { o.threshold_quads.fit.occluded.min_three_side_coverage = 2; }, "2"},
      {"payload_reader", [](DetectorOptions& o) { o.payload_reader = static_cast<PayloadReaderKind>(9); }, "9"},
      {"threshold_quads.fit.outer.bins", [](DetectorOptions& o) { o.threshold_quads.fit.outer.bins = 7; }, "7"},
      {"threshold_quads.fit.outer.tolerance", [](DetectorOptions& o) { o.threshold_quads.fit.outer.tolerance = 1; }, "1"},
      {"threshold_quads.fit.outer.min_dropped",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.min_dropped = kNaN; }, "nan"},
      {"threshold_quads.fit.outer.min_corner_change_px",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.min_corner_change_px = -1; }, "-1"},
      {"threshold_quads.fit.outer.min_points_per_box_px",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.min_points_per_box_px = -1; }, "-1"},
      {"threshold_quads.fit.outer.innermost_min_coverage",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.innermost_min_coverage = 1.5; }, "1.5"},
      {"soft_decode.min_opposite_ratio", [](DetectorOptions& o) { o.soft_decode.min_opposite_ratio = 1.5; }, "1.5"},
      {"threshold_quads.fit.outer.ring_outward_slack",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.ring_outward_slack = 0.3; }, "0.3"},
      {"threshold_quads.fit.outer.ring_slack_sides",
       [](DetectorOptions& o) { o.threshold_quads.fit.outer.ring_slack_sides = -1; }, "-1"},
      {"threshold_quads.blur_sigma", [](DetectorOptions& o) { o.threshold_quads.blur_sigma = kNaN; }, "nan"},
      {"threshold_quads.threshold.tile_size", [](DetectorOptions& o) { o.threshold_quads.threshold.tile_size = 0; }, "0"},
      {"threshold_quads.threshold.min_contrast",
       [](DetectorOptions& o) { o.threshold_quads.threshold.min_contrast = 2; }, "2"},
      {"threshold_quads.boundaries.min_component_pixels",
       [](DetectorOptions& o) { o.threshold_quads.boundaries.min_component_pixels = 0; }, "0"},
      {"threshold_quads.fit.min_points", [](DetectorOptions& o) { o.threshold_quads.fit.min_points = 3; }, "3"},
      {"threshold_quads.fit.max_maxima", [](DetectorOptions& o) { o.threshold_quads.fit.max_maxima = 65; }, "65"},
      {"threshold_quads.fit.max_line_fit_mse", [](DetectorOptions& o) { o.threshold_quads.fit.max_line_fit_mse = 0; }, "0"},
      {"threshold_quads.fit.min_angle_deg", [](DetectorOptions& o) { o.threshold_quads.fit.min_angle_deg = 50; }, "50"},
      {"threshold_quads.fit.min_tag_width", [](DetectorOptions& o) { o.threshold_quads.fit.min_tag_width = -1; }, "-1"},
      {"threshold_quads.fit.dark_inside", [](DetectorOptions& o) { o.threshold_quads.fit.dark_inside = false; }, "0"},
      {"threshold_quads.refine.step_px", [](DetectorOptions& o) { o.threshold_quads.refine.step_px = 0; }, "0"},
      {"threshold_quads.refine.derivative_half_px",
       [](DetectorOptions& o) { o.threshold_quads.refine.derivative_half_px = kInf; }, "inf"},
      {"threshold_quads.refine.sample_spacing_px",
       [](DetectorOptions& o) { o.threshold_quads.refine.sample_spacing_px = -1; }, "-1"},
      {"threshold_quads.refine.range_cell_fraction",
       [](DetectorOptions& o) { o.threshold_quads.refine.range_cell_fraction = 0; }, "0"},
      {"threshold_quads.refine.max_corner_shift_px",
       [](DetectorOptions& o) { o.threshold_quads.refine.max_corner_shift_px = kNaN; }, "nan"},
      {"threshold_quads.refine.gamma", [](DetectorOptions& o) { o.threshold_quads.refine.gamma = 0; }, "0"},
      {"input_gamma", [](DetectorOptions& o) { o.input_gamma = 0; }, "0"},
      {"input_gamma", [](DetectorOptions& o) { o.input_gamma = kNaN; }, "nan"},
      {"input_gamma", [](DetectorOptions& o) { o.input_gamma = 11; }, "11"},
      {"linear_corners.max_corner_shift_px", [](DetectorOptions& o) { o.linear_corners.max_corner_shift_px = 0; }, "0"},
      {"threshold_quads.refine.min_range_px", [](DetectorOptions& o) { o.threshold_quads.refine.min_range_px = 0; }, "0"},
      {"threshold_quads.refine.max_range_px", [](DetectorOptions& o) { o.threshold_quads.refine.max_range_px = 0.5; }, "0.5"},
      {"threshold_quads.refine.end_margin", [](DetectorOptions& o) { o.threshold_quads.refine.end_margin = 0.5; }, "0.5"},
      {"threshold_quads.refine.min_samples", [](DetectorOptions& o) { o.threshold_quads.refine.min_samples = 0; }, "0"},
      {"threshold_quads.refine.iterations", [](DetectorOptions& o) { o.threshold_quads.refine.iterations = 0; }, "0"},
      {"threshold_quads.refine.cells_across", [](DetectorOptions& o) { o.threshold_quads.refine.cells_across = 0; }, "0"},
      {"payload_area.samples_per_side", [](DetectorOptions& o) { o.payload_area.samples_per_side = 0; }, "0"},
      {"payload_area.sample_extent", [](DetectorOptions& o) { o.payload_area.sample_extent = 1.5; }, "1.5"},
      {"payload_area.sharpening", [](DetectorOptions& o) { o.payload_area.sharpening = -0.1; }, "-0.1"},
      {"soft_decode.max_bit_errors", [](DetectorOptions& o) { o.soft_decode.max_bit_errors = -1; }, "-1"},
      {"soft_decode.max_distance", [](DetectorOptions& o) { o.soft_decode.max_distance = -0.5; }, "-0.5"},
      {"soft_decode.min_gap", [](DetectorOptions& o) { o.soft_decode.min_gap = kNaN; }, "nan"},
      {"soft_decode.confidence_cap", [](DetectorOptions& o) { o.soft_decode.confidence_cap = -1; }, "-1"},
      {"camera.fx", [](DetectorOptions& o) { o = with_camera(), o.camera->fx = 0; }, "0"},
      {"camera.fy", [](DetectorOptions& o) { o = with_camera(), o.camera->fy = kNaN; }, "nan"},
      {"camera.cx", [](DetectorOptions& o) { o = with_camera(), o.camera->cx = kInf; }, "inf"},
      {"camera.cy", [](DetectorOptions& o) { o = with_camera(), o.camera->cy = kNaN; }, "nan"},
      {"tag_size", [](DetectorOptions& o) { o = with_camera(), o.tag_size = 0; }, "0"},
      {"tag_size", [](DetectorOptions& o) { o.tag_size = -1; }, "-1"},
      {"distortion.k1", [](DetectorOptions& o) { o = with_camera(), o.distortion = {{kNaN, 0, 0, 0, 0}}; }, "nan"},
      {"distortion.k3", [](DetectorOptions& o) { o = with_camera(), o.distortion = {{0, 0, 0, 0, kInf}}; }, "inf"},
      // Finite but beyond any camera or tag: the pose's arithmetic overflowed into non-rotations.
      {"camera.fx", [](DetectorOptions& o) { o = with_camera(), o.camera->fx = 1e-300; }, "1e-300"},
      {"camera.cy", [](DetectorOptions& o) { o = with_camera(), o.camera->cy = -1; }, "-1"},
      {"tag_size", [](DetectorOptions& o) { o = with_camera(), o.tag_size = 1e300; }, "1e+300"},
      {"distortion.k1", [](DetectorOptions& o) { o = with_camera(), o.distortion = {{1e300, 0, 0, 0, 0}}; }, "1e+300"},
      {"pose_choice.gentle_max_alternative_rms_px",
       [](DetectorOptions& o) { o.pose_choice.gentle_max_alternative_rms_px = -1; }, "-1"},
      {"pose_choice.gentle_samples_per_cell", [](DetectorOptions& o) { o.pose_choice.gentle_samples_per_cell = 0; }, "0"},
      {"pose_choice.gentle_model_blur_px", [](DetectorOptions& o) { o.pose_choice.gentle_model_blur_px = kNaN; }, "nan"},
      {"pose_choice.ambiguous_correlation_gap",
       [](DetectorOptions& o) { o.pose_choice.ambiguous_correlation_gap = kInf; }, "inf"},
      {"threshold_quads.low_contrast.min_contrast",
       [](DetectorOptions& o) { o.threshold_quads.low_contrast.min_contrast = -0.5f; }, "-0.5"},
      {"threshold_quads.low_contrast.max_size_px", [](DetectorOptions& o) { o.threshold_quads.low_contrast.max_size_px = 0; }, "0"},
      {"threshold_quads.low_contrast.min_size_px", [](DetectorOptions& o) { o.threshold_quads.low_contrast.min_size_px = kNaN; }, "nan"},
      {"threshold_quads.low_contrast.min_fill", [](DetectorOptions& o) { o.threshold_quads.low_contrast.min_fill = 1.5; }, "1.5"},
      {"ring_quads.min_size_px", [](DetectorOptions& o) { o.ring_quads.min_size_px = -1; }, "-1"},
      {"ring_quads.max_size_px", [](DetectorOptions& o) { o.ring_quads.max_size_px = 0; }, "0"},
      {"ring_quads.max_fill", [](DetectorOptions& o) { o.ring_quads.max_fill = kNaN; }, "nan"},
      {"ring_quads.min_hole", [](DetectorOptions& o) { o.ring_quads.min_hole = -0.5; }, "-0.5"},
      {"threshold_quads.low_contrast.min_area_px", [](DetectorOptions& o) { o.threshold_quads.low_contrast.min_area_px = -1; }, "-1"},
      {"threshold_quads.low_contrast.min_aspect", [](DetectorOptions& o) { o.threshold_quads.low_contrast.min_aspect = kNaN; }, "nan"},
      {"threshold_quads.low_contrast.margin_px", [](DetectorOptions& o) { o.threshold_quads.low_contrast.margin_px = kInf; }, "inf"},
      {"corner_completion.min_side_px", [](DetectorOptions& o) { o.corner_completion.min_side_px = kNaN; }, "nan"},
      {"corner_completion.max_side_px", [](DetectorOptions& o) { o.corner_completion.max_side_px = 5; }, "5"},
      {"corner_completion.min_move_px", [](DetectorOptions& o) { o.corner_completion.min_move_px = -1; }, "-1"},
      {"corner_completion.spare_bits", [](DetectorOptions& o) { o.corner_completion.spare_bits = -1; }, "-1"},
      {"corner_completion.support_samples", [](DetectorOptions& o) { o.corner_completion.support_samples = 0; }, "0"},
      {"corner_completion.min_support", [](DetectorOptions& o) { o.corner_completion.min_support = 1.5; }, "1.5"},
      {"corner_completion.min_contrast", [](DetectorOptions& o) { o.corner_completion.min_contrast = kInf; }, "inf"},
      {"max_pixels", [](DetectorOptions& o) { o.max_pixels = 0; }, "0"},
      {"max_pixels", [](DetectorOptions& o) { o.max_pixels = kMaxPixelsCeiling + 1; },
       std::to_string(kMaxPixelsCeiling + 1)},
  };
  for (const Case& c : cases) {
    DetectorOptions o;
    c.set(o);
    const std::string m = message(o);
    EXPECT_EQ(m.rfind(c.field + " = " + c.value + ": ", 0), 0u) << "'" << m << "' for " << c.field;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_THROW(Detector{o}, std::invalid_argument) << c.field;
  }
  // The fields without a numeric value: an empty family list, distortion without a camera.
  DetectorOptions o;
  o.families.clear();
  EXPECT_EQ(message(o).rfind("families: ", 0), 0u) << message(o);
  o = DetectorOptions{};
  o.distortion = {{0, 0, 0, 0, 0}};
  EXPECT_EQ(message(o).rfind("distortion: ", 0), 0u) << message(o);
}

TEST(DetectorOptions, DefaultsAndBoundariesPass) {
  EXPECT_EQ(message(DetectorOptions{}), "");
  EXPECT_EQ(message(with_camera()), "");
  DetectorOptions o = with_camera();
  o.distortion = {{-0.3, 0.1, 0.001, -0.001, 0.02}};
  o.max_hamming = 10;  // 36h11: h - 1
  o.min_decision_margin = 1;
  o.seg_sigma = 0;
  o.segmentation.max_edge_cost = M_PI;
  o.segmentation.weight_scale = kMaxWeightScale;
  o.segmentation.min_cluster_size = 1;
  o.segmentation.k_theta = o.segmentation.k_mag = 0;
  o.line_fit.min_length = 0;
  o.quad_search.max_aspect = 1;
  o.quad_search.max_quads = 1;
  o.quad_search.close_enough = CloseEnoughRule::kCode2012;
  o.payload.min_contrast = 0;
  o.max_pixels = kMaxPixelsCeiling;
  EXPECT_EQ(message(o), "");
  o.quad_search.winding_max = o.quad_search.winding_min;  // an empty range
  EXPECT_EQ(message(o).rfind("quad_search.winding_max = -7: ", 0), 0u) << message(o);
}

TEST(DetectorOptions, MaxHammingBelowEveryFamilysDistance) {
  // The smallest minimum distance among the families bounds it: 16h5 (h = 5) allows 0..4.
  DetectorOptions o;
  o.hamming_by_family = false;
  o.families = {"36h11", "16h5"};
  o.max_hamming = 4;
  EXPECT_EQ(message(o), "");
  o.max_hamming = 5;
  EXPECT_EQ(message(o), "max_hamming = 5: must be in 0..4 (below the minimum Hamming distance 5 of family 16h5)");
  // validate(loaded) is the same rule with the families already loaded (the constructor's way).
  const std::vector<TagFamily> loaded = {builtin_family("36h11"), builtin_family("16h5")};
  EXPECT_THROW(o.validate(loaded), std::invalid_argument);
  o.max_hamming = 4;
  EXPECT_NO_THROW(o.validate(loaded));
  EXPECT_THROW(o.validate(std::span(loaded).first(1)), std::invalid_argument);  // not what families names
  // By family each family is capped at (h - 1) / 3, below its distance whatever max_hamming is: it is
  // only a cap, 0..kMaxBitsCorrected, even for a family of distance 2 alone (artoolkitplus-bch, which
  // then corrects nothing; the default profile's 3 once refused it).
  o.hamming_by_family = true;
  o.max_hamming = kMaxBitsCorrected;
  EXPECT_EQ(message(o), "");
  o.max_hamming = kMaxBitsCorrected + 1;
  EXPECT_EQ(message(o), "max_hamming = 17: must be in 0..16");
  DetectorOptions bch;
  bch.families = {"artoolkitplus-bch"};
  EXPECT_EQ(message(bch), "");
  EXPECT_EQ(bch.bits_corrected(builtin_family("artoolkitplus-bch").min_hamming()), 0);
}

TEST(DetectorOptions, TwoFamiliesOfOneNameAreRefused) {
  // A family file whose header names a built-in family: a detection could not say which it is.
  const std::filesystem::path f = std::filesystem::temp_directory_path() / "tagbench-options-shadow.fam";
  std::ofstream(f) << "name: 25h9\nbits: 16\nhamming: 5\ncomplexity: 0\ncount: 1\n0x231b\n";
  DetectorOptions o;
  o.families = {f.string(), "25h9"};
  EXPECT_EQ(message(o), "families: '" + f.string() + "' and '25h9' are both named '25h9': a detection could not say which");
  o.families = {f.string()};
  EXPECT_EQ(message(o), "");
  std::filesystem::remove(f);
}

}  // namespace test_detector_options
