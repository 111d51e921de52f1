// DetectorOptions::validate: every numeric field's domain (detector_options.hpp documents the rules).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "codes/families.hpp"
#include "detect/detector_options.hpp"

namespace tagbench {
namespace {

std::string text(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  return std::string(buf, r.ptr);
}
std::string text(long long v) { return std::to_string(v); }

// One line: "FIELD = VALUE: RULE".
template <class T>
[[noreturn]] void fail(const char* field, T value, const std::string& rule) {
  throw std::invalid_argument(std::string(field) + " = " + text(value) + ": " + rule);
}

void finite_at_least(const char* field, double v, double lo) {
  if (!(std::isfinite(v) && v >= lo)) fail(field, v, "must be finite and >= " + text(lo));
}
void finite_above(const char* field, double v, double lo) {
  if (!(std::isfinite(v) && v > lo)) fail(field, v, "must be finite and > " + text(lo));
}
void within(const char* field, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi)) fail(field, v, "must be in [" + text(lo) + ", " + text(hi) + "]");
}
void int_within(const char* field, long long v, long long lo, long long hi) {
  if (v < lo || v > hi) fail(field, v, "must be in " + text(lo) + ".." + text(hi));
}

void validate_occluded_fit(const OccludedQuadFitOptions& o) {
  within("threshold_quads.fit.occluded.min_radial_cos", o.min_radial_cos, -1, 1);
  int_within("threshold_quads.fit.occluded.min_group_points", o.min_group_points, 4, kMaxPixelsCeiling);
  finite_above("threshold_quads.fit.occluded.split_tolerance_px", o.split_tolerance_px, 0);
  within("threshold_quads.fit.occluded.merge_angle_deg", o.merge_angle_deg, 0, 90);
  finite_above("threshold_quads.fit.occluded.max_line_mse", o.max_line_mse, 0);
  finite_at_least("threshold_quads.fit.occluded.merge_distance_px", o.merge_distance_px, 0);
  finite_at_least("threshold_quads.fit.occluded.inside_tolerance_px", o.inside_tolerance_px, 0);
  int_within("threshold_quads.fit.occluded.max_lines", o.max_lines, 4, 16);  // C(16, 4) = 1820 sets at most
  int_within("threshold_quads.fit.occluded.max_runs", o.max_runs, 4, 1000);
  within("threshold_quads.fit.occluded.min_side_fraction", o.min_side_fraction, 0, 1);
  within("threshold_quads.fit.occluded.min_total_coverage", o.min_total_coverage, 0, 4);
  within("threshold_quads.fit.occluded.min_on_lines", o.min_on_lines, 0, 1);
  within("threshold_quads.fit.occluded.max_inside_outliers", o.max_inside_outliers, 0, 1);
  within("threshold_quads.fit.occluded.min_three_side_coverage", o.min_three_side_coverage, 0, 1);
}

void validate_defocus_read(const DefocusReadOptions& f) {
  for (std::size_t i = 0; i < f.radii_cells.size(); ++i) {
    finite_at_least("defocus_read.radii_cells", f.radii_cells[i], 0);
    if (i > 0 && !(f.radii_cells[i] > f.radii_cells[i - 1]))
      fail("defocus_read.radii_cells", f.radii_cells[i], "must be ascending");
  }
  finite_at_least("defocus_read.regularization", f.regularization, 0);
  int_within("defocus_read.max_hypothesis_bits", f.max_hypothesis_bits, 0, 64);
  finite_at_least("defocus_read.max_hypothesis_cost", f.max_hypothesis_cost, 0);
  int_within("defocus_read.spare_bits", f.spare_bits, 0, 64);
  int_within("defocus_read.samples_per_cell", f.samples_per_cell, 1, 8);
  finite_above("defocus_read.final_step_px", f.final_step_px, 0);
  if (!(std::isfinite(f.initial_step_px) && f.initial_step_px >= f.final_step_px))
    fail("defocus_read.initial_step_px", f.initial_step_px, "must be finite and >= defocus_read.final_step_px");
  finite_at_least("defocus_read.max_corner_shift_px", f.max_corner_shift_px, 0);
  if (f.min_family_hamming < 0) fail("defocus_read.min_family_hamming", static_cast<long long>(f.min_family_hamming), "must be >= 0");
  finite_at_least("defocus_read.min_side_px", f.min_side_px, 0);
  if (!(f.max_side_px >= f.min_side_px)) fail("defocus_read.max_side_px", f.max_side_px, "must be >= defocus_read.min_side_px");
}

void validate_threshold_quads(const ThresholdQuadOptions& q) {
  finite_at_least("threshold_quads.blur_sigma", q.blur_sigma, 0);
  finite_above("threshold_quads.noise_blur.min_noise_grey", q.noise_blur.min_noise_grey, 0);
  finite_above("threshold_quads.noise_blur.sigma", q.noise_blur.sigma, 0);
  int_within("threshold_quads.threshold.tile_size", q.threshold.tile_size, 1, 256);
  within("threshold_quads.threshold.min_contrast", q.threshold.min_contrast, 0, 1);
  int_within("threshold_quads.refine_check.payload_width", q.refine_check.payload_width, 1, 8);
  within("threshold_quads.refine_check.min_contrast", q.refine_check.min_contrast, 0, 1);
  within("threshold_quads.threshold.low_contrast", q.threshold.low_contrast, 0, 1);
  finite_at_least("threshold_quads.threshold.weber_ratio", q.threshold.weber_ratio, 0);
  finite_at_least("threshold_quads.threshold.mean_sigma", q.threshold.mean_sigma, 0);
  int_within("threshold_quads.boundaries.min_component_pixels", q.boundaries.min_component_pixels, 1,
             kMaxPixelsCeiling);
  int_within("threshold_quads.fit.min_points", q.fit.min_points, 4, kMaxPixelsCeiling);
  int_within("threshold_quads.fit.max_maxima", q.fit.max_maxima, 4, 64);
  finite_above("threshold_quads.fit.max_line_fit_mse", q.fit.max_line_fit_mse, 0);
  within("threshold_quads.fit.min_angle_deg", q.fit.min_angle_deg, 0, 45);
  finite_at_least("threshold_quads.fit.min_tag_width", q.fit.min_tag_width, 0);
  if (!q.fit.dark_inside && !q.fit.light_inside)
    fail("threshold_quads.fit.dark_inside", 0LL, "dark_inside and light_inside both false: no quad can be found");
  const EdgeRefineOptions& r = q.refine;
  finite_above("threshold_quads.refine.step_px", r.step_px, 0);
  finite_above("threshold_quads.refine.derivative_half_px", r.derivative_half_px, 0);
  finite_above("threshold_quads.refine.sample_spacing_px", r.sample_spacing_px, 0);
  finite_above("threshold_quads.refine.range_cell_fraction", r.range_cell_fraction, 0);
  finite_above("threshold_quads.refine.max_corner_shift_px", r.max_corner_shift_px, 0);
  finite_above("threshold_quads.refine.gamma", r.gamma, 0);
  finite_above("threshold_quads.refine.min_range_px", r.min_range_px, 0);
  if (!(std::isfinite(r.max_range_px) && r.max_range_px >= r.min_range_px))
    fail("threshold_quads.refine.max_range_px", r.max_range_px,
         "must be finite and >= threshold_quads.refine.min_range_px (" + text(r.min_range_px) + ")");
  if (!(r.end_margin >= 0 && r.end_margin < 0.5))
    fail("threshold_quads.refine.end_margin", r.end_margin, "must be in [0, 0.5)");
  int_within("threshold_quads.refine.min_samples", r.min_samples, 1, 1 << 20);
  int_within("threshold_quads.refine.iterations", r.iterations, 1, 100);
  int_within("threshold_quads.refine.cells_across", r.cells_across, 1, 64);
  validate_occluded_fit(q.fit.occluded);
  within("threshold_quads.low_contrast.min_contrast", q.low_contrast.min_contrast, 0, 1);
  finite_above("threshold_quads.low_contrast.max_size_px", q.low_contrast.max_size_px, 0);
  finite_at_least("threshold_quads.low_contrast.min_size_px", q.low_contrast.min_size_px, 0);
  within("threshold_quads.low_contrast.min_fill", q.low_contrast.min_fill, 0, 1);
  finite_at_least("threshold_quads.low_contrast.min_area_px", q.low_contrast.min_area_px, 0);
  within("threshold_quads.low_contrast.min_aspect", q.low_contrast.min_aspect, 0, 1);
  finite_at_least("threshold_quads.low_contrast.margin_px", q.low_contrast.margin_px, 0);
  int_within("threshold_quads.fit.outer.bins", q.fit.outer.bins, 8, 1024);
  if (!(q.fit.outer.tolerance > 0 && q.fit.outer.tolerance < 1))
    fail("threshold_quads.fit.outer.tolerance", q.fit.outer.tolerance, "must be in (0, 1)");
  within("threshold_quads.fit.outer.min_dropped", q.fit.outer.min_dropped, 0, 1);
  finite_at_least("threshold_quads.fit.outer.min_corner_change_px", q.fit.outer.min_corner_change_px, 0);
  if (!(q.fit.outer.max_size_px > 0))  // infinity allowed: every group
    fail("threshold_quads.fit.outer.max_size_px", q.fit.outer.max_size_px, "must be > 0");
  finite_at_least("threshold_quads.fit.outer.min_points_per_box_px", q.fit.outer.min_points_per_box_px, 0);
  within("threshold_quads.fit.outer.innermost_min_coverage", q.fit.outer.innermost_min_coverage, 0, 1);
  within("threshold_quads.fit.outer.ring_min_share", q.fit.outer.ring_min_share, 0, 1);
  finite_at_least("threshold_quads.fit.outer.ring_min_step", q.fit.outer.ring_min_step, 0);
  within("threshold_quads.fit.outer.min_side_ratio", q.fit.outer.min_side_ratio, 0, 1);
  within("threshold_quads.fit.outer.ring_outward_slack", q.fit.outer.ring_outward_slack, 0, 0.25);
  int_within("threshold_quads.fit.outer.ring_slack_sides", q.fit.outer.ring_slack_sides, 0, 4);
}

void validate_occlusion_refit(const OcclusionRefitOptions& o) {
  finite_above("occlusion.sample_spacing_px", o.sample_spacing_px, 0);
  finite_at_least("occlusion.end_margin_px", o.end_margin_px, 0);
  within("occlusion.agree_fraction", o.agree_fraction, 0, 1);
  within("occlusion.max_disagree", o.max_disagree, 0, 1);
  int_within("occlusion.erode_samples", o.erode_samples, 0, 1000);
  within("occlusion.min_visible", o.min_visible, 0, 1);
  within("occlusion.min_median_contrast", o.min_median_contrast, 0, 1);
  finite_above("occlusion.max_corner_shift_cells", o.max_corner_shift_cells, 0);
  int_within("occlusion.iterations", o.iterations, 1, 100);
  finite_at_least("occlusion.min_cell_px", o.min_cell_px, 0);
}

void validate_photometric(const std::string& name, const PhotometricRefineOptions& p) {
  int_within((name + ".iterations").c_str(), p.iterations, 1, 100);
  int_within((name + ".min_pixels").c_str(), p.min_pixels, 1, kMaxPixelsCeiling);
  int_within((name + ".max_pixels").c_str(), p.max_pixels, p.min_pixels, kMaxPixelsCeiling);
  if (!(p.margin_cells >= 0 && p.margin_cells < 1)) fail((name + ".margin_cells").c_str(), p.margin_cells, "must be in [0, 1)");
  finite_above((name + ".band_px").c_str(), p.band_px, 0);
  finite_at_least((name + ".pixels_per_side_px").c_str(), p.pixels_per_side_px, 0);
  finite_above((name + ".initial_blur_px").c_str(), p.initial_blur_px, 0);
  finite_above((name + ".max_corner_shift_px").c_str(), p.max_corner_shift_px, 0);
  finite_above((name + ".max_blur_cells").c_str(), p.max_blur_cells, 0);
  finite_at_least((name + ".min_black_square_px").c_str(), p.min_black_square_px, 0);
  finite_at_least((name + ".huber").c_str(), p.huber, 0);
  within((name + ".min_contrast").c_str(), p.min_contrast, 0, 1);
}

void validate_border_kink(const std::string& name, const BorderKinkOptions& k) {
  int_within((name + ".samples").c_str(), k.samples, 4, 256);
  if (!(k.end_margin >= 0 && k.end_margin < 0.5)) fail((name + ".end_margin").c_str(), k.end_margin, "must be in [0, 0.5)");
  finite_above((name + ".range_cells").c_str(), k.range_cells, 0);
  finite_above((name + ".min_range_px").c_str(), k.min_range_px, 0);
  finite_above((name + ".step_px").c_str(), k.step_px, 0);
  finite_above((name + ".derivative_half_px").c_str(), k.derivative_half_px, 0);
  within((name + ".max_fold_offset").c_str(), k.max_fold_offset, 0, 0.9);
  int_within((name + ".cells_across").c_str(), k.cells_across, 1, 1000);
}

}  // namespace

DetectorOptions DetectorOptions::paper() {
  DetectorOptions o;
  o.quad_finder = QuadFinderKind::kGradient;
  o.payload_reader = PayloadReaderKind::kPoint;
  o.photometric.enabled = false;
  o.occlusion_refit = false;
  o.max_hamming = 1;
  o.hamming_by_family = false;
  o.bent.enabled = false;
  o.code_refit.enabled = false;
  o.defocus_read.enabled = false;
  o.corner_completion.enabled = false;
  o.photometric_guard.enabled = false;
  o.pose_choice.enabled = false;
  o.second_look.enabled = false;
  o.group_look.enabled = false;
  o.printed_square.enabled = false;
  o.ring_quads.enabled = false;
  o.line_quads.enabled = false;
  o.coarse_pass.enabled = false;
  o.dark_outlines.enabled = false;
  o.soft_decode.enabled = false;
  o.threshold_quads.low_contrast.enabled = false;
  o.suppress_overlaps = false;
  o.linear_corners.enabled = false;
  return o;
}

DetectorOptions DetectorOptions::thorough() {
  DetectorOptions o;
  o.line_quads = LineQuadOptions{};  // the edges at full resolution, with the options' own defaults
  o.line_quads.enabled = true;
  o.coarse_pass.enabled = true;
  return o;
}

std::optional<DetectorOptions> DetectorOptions::named_profile(std::string_view name) {
  if (name == "default") return DetectorOptions{};
  if (name == "thorough") return thorough();
  if (name == "paper") return paper();
  return std::nullopt;
}

int DetectorOptions::bits_corrected(int min_hamming) const {
  return bits_corrected_for(min_hamming, max_hamming, hamming_by_family);
}

void DetectorOptions::validate(std::span<const TagFamily> loaded) const {
  if (families.empty()) throw std::invalid_argument("families: empty: give at least one tag family");
  if (loaded.size() != families.size())
    throw std::invalid_argument("families: " + std::to_string(families.size()) + " named but " +
                                std::to_string(loaded.size()) + " loaded");
  // Every family's bits corrected stay below its distance. By family each is capped at (h - 1) / 3,
  // below h whatever max_hamming is: max_hamming is then only a cap, 0..16 (a family of distance 2,
  // such as artoolkitplus-bch, corrects none). Else max_hamming must be below the smallest distance.
  int h_min = loaded.front().min_hamming();
  std::string h_family = loaded.front().name();
  for (const TagFamily& f : loaded)
    if (f.min_hamming() < h_min) h_min = f.min_hamming(), h_family = f.name();
  const int k_max = hamming_by_family ? kMaxBitsCorrected : std::max(0, h_min - 1);
  if (max_hamming < 0 || max_hamming > k_max)
    fail("max_hamming", static_cast<long long>(max_hamming),
         "must be in 0.." + std::to_string(k_max) +
             (hamming_by_family ? std::string()
                                : " (below the minimum Hamming distance " + std::to_string(h_min) + " of family " +
                                      h_family + ")"));
  // Two families of one name: a detection names its family, so it could not say which.
  for (std::size_t i = 0; i < loaded.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (loaded[i].name() == loaded[j].name())
        throw std::invalid_argument("families: '" + families[j] + "' and '" + families[i] +
                                    "' are both named '" + loaded[i].name() + "': a detection could not say which");
  within("min_decision_margin", min_decision_margin, 0, 1);
  finite_at_least("seg_sigma", seg_sigma, 0);
  finite_at_least("decode_sigma", decode_sigma, 0);
  within("input_gamma", input_gamma, 0.1, 10);
  finite_above("linear_corners.max_corner_shift_px", linear_corners.max_corner_shift_px, 0);

  finite_at_least("segmentation.min_mag", segmentation.min_mag, 0);
  if (!(std::isfinite(segmentation.max_edge_cost) && segmentation.max_edge_cost > 0 &&
        segmentation.max_edge_cost <= std::numbers::pi))
    fail("segmentation.max_edge_cost", segmentation.max_edge_cost, "must be in (0, pi] radians");
  int_within("segmentation.weight_scale", segmentation.weight_scale, 1, kMaxWeightScale);
  finite_at_least("segmentation.k_theta", segmentation.k_theta, 0);
  finite_at_least("segmentation.k_mag", segmentation.k_mag, 0);
  int_within("segmentation.min_cluster_size", segmentation.min_cluster_size, 1, kMaxPixelsCeiling);

  finite_at_least("line_fit.min_length", line_fit.min_length, 0);

  switch (quad_search.close_enough) {
    case CloseEnoughRule::kPaper2011:
    case CloseEnoughRule::kCode2010:
    case CloseEnoughRule::kCode2012: break;
    default:
      fail("quad_search.close_enough", static_cast<long long>(quad_search.close_enough),
           "must be kPaper2011, kCode2010 or kCode2012");
  }
  finite_above("quad_search.min_tag_size", quad_search.min_tag_size, 0);
  finite_at_least("quad_search.max_aspect", quad_search.max_aspect, 1);
  if (!std::isfinite(quad_search.winding_min)) fail("quad_search.winding_min", quad_search.winding_min, "must be finite");
  if (!(std::isfinite(quad_search.winding_max) && quad_search.winding_max > quad_search.winding_min))
    fail("quad_search.winding_max", quad_search.winding_max,
         "must be finite and > quad_search.winding_min (" + text(quad_search.winding_min) + ")");
  finite_above("quad_search.grid_cell", quad_search.grid_cell, 0);
  if (quad_search.max_quads < 1)
    fail("quad_search.max_quads", static_cast<long long>(quad_search.max_quads), "must be >= 1");

  within("payload.min_contrast", payload.min_contrast, 0, 1);

  if (quad_finder != QuadFinderKind::kGradient && quad_finder != QuadFinderKind::kThreshold)
    fail("quad_finder", static_cast<long long>(quad_finder), "must be kGradient or kThreshold");
  if (payload_reader != PayloadReaderKind::kPoint && payload_reader != PayloadReaderKind::kArea)
    fail("payload_reader", static_cast<long long>(payload_reader), "must be kPoint or kArea");
  validate_threshold_quads(threshold_quads);
  validate_photometric("photometric", photometric);
  validate_photometric("code_refit.refine", code_refit.refine);
  int_within("code_refit.max_bits", code_refit.max_bits, 0, 64);
  int_within("code_refit.spare_bits", code_refit.spare_bits, 0, 64);
  finite_at_least("code_refit.max_weak_distance", code_refit.max_weak_distance, 0);
  if (code_refit.min_family_hamming < 0) fail("code_refit.min_family_hamming", static_cast<long long>(code_refit.min_family_hamming), "must be >= 0");
  finite_at_least("code_refit.min_side_px", code_refit.min_side_px, 0);
  finite_at_least("corner_completion.min_side_px", corner_completion.min_side_px, 0);
  if (!(corner_completion.max_side_px >= corner_completion.min_side_px))
    fail("corner_completion.max_side_px", corner_completion.max_side_px, "must be >= corner_completion.min_side_px");
  finite_at_least("corner_completion.min_move_px", corner_completion.min_move_px, 0);
  int_within("corner_completion.spare_bits", corner_completion.spare_bits, 0, 64);
  int_within("corner_completion.support_samples", corner_completion.support_samples, 1, 1000);
  within("corner_completion.min_support", corner_completion.min_support, 0, 1);
  finite_at_least("corner_completion.min_contrast", corner_completion.min_contrast, 0);
  validate_defocus_read(defocus_read);
  if (!(code_refit.max_side_px >= code_refit.min_side_px)) fail("code_refit.max_side_px", code_refit.max_side_px, "must be >= code_refit.min_side_px");
  validate_occlusion_refit(occlusion);
  finite_above("second_look.max_size_px", second_look.max_size_px, 0);
  finite_at_least("second_look.min_size_px", second_look.min_size_px, 0);
  finite_at_least("second_look.margin_px", second_look.margin_px, 0);
  within("second_look.min_class_gap", second_look.min_class_gap, 0, 1);
  finite_at_least("second_look.min_corner_change_px", second_look.min_corner_change_px, 0);
  finite_at_least("group_look.min_size_px", group_look.min_size_px, 0);
  finite_above("group_look.max_size_px", group_look.max_size_px, 0);
  finite_above("group_look.min_window_px", group_look.min_window_px, 0);
  finite_at_least("group_look.margin_px", group_look.margin_px, 0);
  if (group_look.min_points < 1) fail("group_look.min_points", static_cast<long long>(group_look.min_points), "must be >= 1");
  if (group_look.max_windows < 0) fail("group_look.max_windows", static_cast<long long>(group_look.max_windows), "must be >= 0");
  finite_at_least("ring_quads.min_size_px", ring_quads.min_size_px, 0);
  finite_above("ring_quads.max_size_px", ring_quads.max_size_px, 0);
  finite_above("ring_quads.max_fill", ring_quads.max_fill, 0);
  finite_at_least("ring_quads.min_hole", ring_quads.min_hole, 0);
  within("coarse_pass.min_contrast", coarse_pass.min_contrast, 0, 1);
  finite_at_least("coarse_pass.min_tag_px", coarse_pass.min_tag_px, 0);
  finite_at_least("dark_outlines.min_size_px", dark_outlines.min_size_px, 0);
  finite_above("dark_outlines.max_size_px", dark_outlines.max_size_px, 0);
  int_within("dark_outlines.min_groups", dark_outlines.min_groups, 2, 1 << 20);
  int_within("dark_outlines.max_groups", dark_outlines.max_groups, dark_outlines.min_groups, 1 << 20);
  int_within("dark_outlines.slack_sides", dark_outlines.slack_sides, 0, 4);
  finite_at_least("dark_outlines.pair_margin_px", dark_outlines.pair_margin_px, 0);
  int_within("dark_outlines.pair_min_points", dark_outlines.pair_min_points, 0, 1 << 30);
  within("dark_outlines.pair_min_share", dark_outlines.pair_min_share, 0, 1);
  finite_above("line_quads.max_side_px", line_quads.max_side_px, 0);
  finite_at_least("line_quads.min_side_px", line_quads.min_side_px, 0);
  finite_above("line_quads.scale", line_quads.scale, 0);
  within("line_quads.scale", line_quads.scale, 0, 1);
  int_within("line_quads.spare_bits", line_quads.spare_bits, 0, 16);
  finite_at_least("line_quads.segments.sigma", line_quads.segments.sigma, 0);
  finite_above("line_quads.segments.angle_tolerance_deg", line_quads.segments.angle_tolerance_deg, 0);
  within("line_quads.segments.angle_tolerance_deg", line_quads.segments.angle_tolerance_deg, 0, 90);
  finite_above("line_quads.segments.min_gradient", line_quads.segments.min_gradient, 0);
  finite_at_least("line_quads.segments.min_seed_gradient", line_quads.segments.min_seed_gradient, 0);
  finite_at_least("line_quads.segments.min_density", line_quads.segments.min_density, 0);
  within("line_quads.segments.log_eps", line_quads.segments.log_eps, -100, 100);
  finite_at_least("line_quads.segments.min_length_px", line_quads.segments.min_length_px, 0);
  int_within("line_quads.segments.max_region_pixels", line_quads.segments.max_region_pixels, 0, kMaxPixelsCeiling);
  int_within("line_quads.segments.max_cuts", line_quads.segments.max_cuts, 0, 100);
  int_within("line_quads.segments.straight_sides", line_quads.segments.straight_sides, 0, 2);
  finite_above("line_quads.segments.straight_check_px", line_quads.segments.straight_check_px, 0);
  finite_at_least("photometric_guard.max_kink_px", photometric_guard.max_kink_px, 0);
  finite_at_least("photometric_guard.max_blur_px", photometric_guard.max_blur_px, 0);
  finite_at_least("photometric_guard.min_kink_significance", photometric_guard.min_kink_significance, 0);
  finite_at_least("photometric_guard.min_side_px", photometric_guard.min_side_px, 0);
  finite_at_least("photometric_guard.hidden_depth_cells", photometric_guard.hidden_depth_cells, 0);
  finite_at_least("photometric_guard.hidden_pad_cells", photometric_guard.hidden_pad_cells, 0);
  finite_at_least("photometric_guard.keep_scale_min_blur_px", photometric_guard.keep_scale_min_blur_px, 0);
  validate_border_kink("photometric_guard.kink", photometric_guard.kink);
  finite_at_least("pose_choice.max_alternative_rms_px", pose_choice.max_alternative_rms_px, 0);
  finite_at_least("pose_choice.min_correlation_gain", pose_choice.min_correlation_gain, 0);
  within("pose_choice.min_view_angle_deg", pose_choice.min_view_angle_deg, 0, 90);
  int_within("pose_choice.samples_per_cell", pose_choice.samples_per_cell, 1, 16);
  finite_at_least("pose_choice.ambiguous_correlation_gap", pose_choice.ambiguous_correlation_gap, 0);
  finite_at_least("pose_choice.gentle_max_alternative_rms_px", pose_choice.gentle_max_alternative_rms_px, 0);
  finite_at_least("pose_choice.gentle_min_correlation_gain", pose_choice.gentle_min_correlation_gain, 0);
  int_within("pose_choice.gentle_samples_per_cell", pose_choice.gentle_samples_per_cell, 1, 16);
  finite_at_least("pose_choice.gentle_model_blur_px", pose_choice.gentle_model_blur_px, 0);
  finite_at_least("bent.min_kink_px", bent.min_kink_px, 0);
  validate_border_kink("bent.kink", bent.kink);
  int_within("bent.precheck_samples", bent.precheck_samples, 4, 256);
  within("bent.precheck_fraction", bent.precheck_fraction, 0, 1);
  finite_at_least("bent.min_side_px", bent.min_side_px, 0);
  int_within("payload_area.samples_per_side", payload_area.samples_per_side, 1, 16);
  within("payload_area.sample_extent", payload_area.sample_extent, 0, 1);
  finite_at_least("payload_area.sharpening", payload_area.sharpening, 0);
  finite_at_least("payload_area.small_cell_px", payload_area.small_cell_px, 0);
  finite_at_least("payload_area.small_cell_sharpening", payload_area.small_cell_sharpening, 0);
  within("payload_area.self_threshold.max_light_black_ring", payload_area.self_threshold.max_light_black_ring, 0, 1);
  int_within("payload_area.self_threshold.spare_bits", payload_area.self_threshold.spare_bits, 0, 64);
  int_within("payload_area.self_threshold.min_family_hamming", payload_area.self_threshold.min_family_hamming, 0, 64);
  int_within("soft_decode.max_bit_errors", soft_decode.max_bit_errors, 0, 64);
  finite_at_least("soft_decode.max_distance", soft_decode.max_distance, 0);
  finite_at_least("soft_decode.min_gap", soft_decode.min_gap, 0);
  finite_at_least("soft_decode.confidence_cap", soft_decode.confidence_cap, 0);
  within("soft_decode.min_opposite_ratio", soft_decode.min_opposite_ratio, 0, 1);

  if (camera) {
    // Bounds far outside any camera and tag, inside which the pose's arithmetic stays well scaled
    // (at 1e300 m or a 1e-300 px focal length it overflowed into poses that were not rotations).
    within("camera.fx", camera->fx, 1e-2, 1e8);
    within("camera.fy", camera->fy, 1e-2, 1e8);
    within("camera.cx", camera->cx, 0, 1e8);
    within("camera.cy", camera->cy, 0, 1e8);
    within("tag_size", tag_size, 1e-6, 1e6);  // metres, needed for the pose
  } else {
    finite_at_least("tag_size", tag_size, 0);  // unused without a camera
  }
  if (distortion) {
    if (!camera) throw std::invalid_argument("distortion: given without camera intrinsics (camera)");
    static constexpr const char* kNames[5] = {"distortion.k1", "distortion.k2", "distortion.p1", "distortion.p2",
                                              "distortion.k3"};
    for (std::size_t i = 0; i < 5; ++i)
      within(kNames[i], (*distortion)[i], -1e4, 1e4);
  }
  int_within("max_pixels", max_pixels, 1, kMaxPixelsCeiling);
}

void DetectorOptions::validate() const {
  std::vector<TagFamily> loaded;
  for (const auto& f : families) loaded.push_back(load_family(f));
  validate(loaded);
}

}  // namespace tagbench
