// A variant's KEY=VALUE settings applied to DetectorOptions (detector_variants.hpp).
#include "raytrace/detector_variants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>

namespace tagbench::bench {
namespace {

// The whole of `text` as a finite number, or nullopt (empty, trailing characters, inf, nan).
std::optional<double> parse_number(const std::string& text) {
  char* to = nullptr;
  const double x = std::strtod(text.c_str(), &to);
  if (text.empty() || to != text.c_str() + text.size() || !std::isfinite(x)) return std::nullopt;
  return x;
}

}  // namespace

void apply_detector_variant(DetectorOptions& o, const std::string& spec, const std::string& name) {
  std::size_t pos = 0;
  while (pos < spec.size()) {
    const std::size_t end = std::min(spec.find('/', pos), spec.size());
    const std::string kv = spec.substr(pos, end - pos);
    pos = end + 1;
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("detector '" + name + "': '" + kv + "' is not KEY=VALUE");
    const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
    const auto bad_value = [&](const char* want) {
      return std::invalid_argument("detector '" + name + "': " + k + "='" + v + "' is not " + want);
    };
    if (k == "finder") {
      if (v != "gradient" && v != "threshold") throw bad_value("gradient or threshold");
      o.quad_finder = v == "gradient" ? QuadFinderKind::kGradient : QuadFinderKind::kThreshold;
      continue;
    }
    if (k == "reader") {
      if (v != "point" && v != "area") throw bad_value("point or area");
      o.payload_reader = v == "point" ? PayloadReaderKind::kPoint : PayloadReaderKind::kArea;
      continue;
    }
    if (k == "dfr_radii") {  // the defocus reading's radii in cells, colon-separated: 0:0.7:0.9:1.1
      o.defocus_read.radii_cells.clear();
      for (std::size_t a = 0; a <= v.size();) {
        const std::size_t b = std::min(v.find(':', a), v.size());
        const auto r = parse_number(v.substr(a, b - a));
        if (!r) throw bad_value("a colon-separated list of numbers");
        o.defocus_read.radii_cells.push_back(*r);
        a = b + 1;
      }
      continue;
    }
    const auto number = parse_number(v);
    if (!number) throw bad_value("a number");
    const double x = *number;
    if (k == "k") o.payload_area.samples_per_side = static_cast<int>(x);
    else if (k == "extent") o.payload_area.sample_extent = x;
    else if (k == "sharpen") o.payload_area.sharpening = x;
    else if (k == "small_px") o.payload_area.small_cell_px = x;
    else if (k == "small_sharpen") o.payload_area.small_cell_sharpening = x;
    else if (k == "refine") o.threshold_quads.refine_edges = x != 0;
    else if (k == "gamma") o.threshold_quads.refine.gamma = x;
    else if (k == "refine_iter") o.threshold_quads.refine.iterations = static_cast<int>(x);
    else if (k == "refine_spacing") o.threshold_quads.refine.sample_spacing_px = x;
    else if (k == "hamming") o.max_hamming = static_cast<int>(x), o.hamming_by_family = false;  // every family
    else if (k == "byfamily") o.hamming_by_family = x != 0;
    else if (k == "tile") o.threshold_quads.threshold.tile_size = static_cast<int>(x);
    else if (k == "contrast") o.threshold_quads.threshold.min_contrast = static_cast<float>(x);
    else if (k == "low_contrast") o.threshold_quads.threshold.low_contrast = static_cast<float>(x);
    else if (k == "weber") o.threshold_quads.threshold.weber_ratio = static_cast<float>(x);
    else if (k == "tmean") o.threshold_quads.threshold.mean_sigma = static_cast<float>(x);
    else if (k == "minpix") o.threshold_quads.boundaries.min_component_pixels = static_cast<std::uint32_t>(x);
    else if (k == "minwidth") o.threshold_quads.fit.min_tag_width = x;
    else if (k == "margin") o.min_decision_margin = x;
    else if (k == "tblur") o.threshold_quads.blur_sigma = x;
    else if (k == "nblur") o.threshold_quads.noise_blur.enabled = x != 0;
    else if (k == "soft_area") o.soft_decode.min_area_ratio = x;
    else if (k == "soft_opp") o.soft_decode.min_opposite_ratio = x;
    else if (k == "nblur_min") o.threshold_quads.noise_blur.min_noise_grey = x;
    else if (k == "nblur_sigma") o.threshold_quads.noise_blur.sigma = x;
    else if (k == "minpts") o.threshold_quads.fit.min_points = static_cast<int>(x);
    else if (k == "maxima") o.threshold_quads.fit.max_maxima = static_cast<int>(x);
    else if (k == "mse") o.threshold_quads.fit.max_line_fit_mse = x;
    else if (k == "dark8") o.threshold_quads.dark_eight_connected = x != 0;
    else if (k == "oneside") o.threshold_quads.fit.refit_one_side = x != 0;
    else if (k == "photo") o.photometric.enabled = x != 0;
    else if (k == "photo_iter") o.photometric.iterations = static_cast<int>(x);
    else if (k == "photo_px") o.photometric.max_pixels = static_cast<int>(x);
    else if (k == "photo_per_side") o.photometric.pixels_per_side_px = x;
    else if (k == "photo_shift") o.photometric.max_corner_shift_px = x;
    else if (k == "photo_blur") o.photometric.max_blur_cells = x;
    else if (k == "photo_band") o.photometric.band_px = x;
    else if (k == "photo_margin") o.photometric.margin_cells = x;
    else if (k == "photo_huber") o.photometric.huber = x;
    else if (k == "input_gamma") o.input_gamma = x;
    else if (k == "lincorners") o.linear_corners.enabled = x != 0;
    else if (k == "lin_shift") o.linear_corners.max_corner_shift_px = x;
    else if (k == "photo_dots") o.photometric.column_dot_sums = x != 0;
    else if (k == "pguard") o.photometric_guard.enabled = x != 0;
    else if (k == "pguard_kink") o.photometric_guard.max_kink_px = x;
    else if (k == "pguard_blur") o.photometric_guard.max_blur_px = x;
    else if (k == "pguard_sig") o.photometric_guard.min_kink_significance = x;
    else if (k == "pguard_side") o.photometric_guard.min_side_px = x;
    else if (k == "pguard_fold") o.photometric_guard.kink.max_fold_offset = x;
    else if (k == "pguard_range") o.photometric_guard.kink.range_cells = x;
    else if (k == "pguard_samples") o.photometric_guard.kink.samples = static_cast<int>(x);
    else if (k == "pguard_hidden") o.photometric_guard.skip_hidden_sides = x != 0;
    else if (k == "pguard_mask") o.photometric_guard.hidden_depth_cells = x;
    else if (k == "pguard_pad") o.photometric_guard.hidden_pad_cells = x;
    else if (k == "pguard_blurscale") o.photometric_guard.blurred_keep_scale = x != 0;
    else if (k == "pguard_blurscale_px") o.photometric_guard.keep_scale_min_blur_px = x;
    else if (k == "posechoice") o.pose_choice.enabled = x != 0;
    else if (k == "posechoice_rms") o.pose_choice.max_alternative_rms_px = x;
    else if (k == "posechoice_gain") o.pose_choice.min_correlation_gain = x;
    else if (k == "posechoice_view") o.pose_choice.min_view_angle_deg = x;
    else if (k == "posechoice_lens") o.pose_choice.with_lens = x != 0;
    else if (k == "posechoice_samples") o.pose_choice.samples_per_cell = static_cast<int>(x);
    else if (k == "posechoice_ambig") o.pose_choice.ambiguous_correlation_gap = x;
    else if (k == "posechoice_gentle_rms") o.pose_choice.gentle_max_alternative_rms_px = x;
    else if (k == "posechoice_gentle_gain") o.pose_choice.gentle_min_correlation_gain = x;
    else if (k == "posechoice_gentle_samples") o.pose_choice.gentle_samples_per_cell = static_cast<int>(x);
    else if (k == "posechoice_gentle_blur") o.pose_choice.gentle_model_blur_px = x;
    else if (k == "bent") o.bent.enabled = x != 0;
    else if (k == "cref") o.code_refit.enabled = x != 0;
    else if (k == "dfr") o.defocus_read.enabled = x != 0;
    else if (k == "dfr_bits") o.defocus_read.max_hypothesis_bits = static_cast<int>(x);
    else if (k == "dfr_cost") o.defocus_read.max_hypothesis_cost = x;
    else if (k == "dfr_spare") o.defocus_read.spare_bits = static_cast<int>(x);
    else if (k == "dfr_m") o.defocus_read.samples_per_cell = static_cast<int>(x);
    else if (k == "dfr_reg") o.defocus_read.regularization = x;
    else if (k == "dfr_shift") o.defocus_read.max_corner_shift_px = x;
    else if (k == "dfr_min") o.defocus_read.min_side_px = x;
    else if (k == "dfr_max") o.defocus_read.max_side_px = x;
    else if (k == "dfr_rmax") {  // radii 0 and 0.6 .. x in steps of 0.1
      o.defocus_read.radii_cells = {0};
      for (int i = 6; i <= static_cast<int>(std::lround(10 * x)); ++i) o.defocus_read.radii_cells.push_back(0.1 * i);
    }
    else if (k == "cref_bits") o.code_refit.max_bits = static_cast<int>(x);
    else if (k == "cref_weak") o.code_refit.max_weak_distance = x;
    else if (k == "cref_spare") o.code_refit.spare_bits = static_cast<int>(x);
    else if (k == "cref_fam") o.code_refit.min_family_hamming = static_cast<int>(x);
    else if (k == "cref_min") o.code_refit.min_side_px = x;
    else if (k == "cref_max") o.code_refit.max_side_px = x;
    else if (k == "cref_iter") o.code_refit.refine.iterations = static_cast<int>(x);
    else if (k == "cref_blur") o.code_refit.refine.initial_blur_px = x;
    else if (k == "cref_band") o.code_refit.refine.band_px = x;
    else if (k == "cref_shift") o.code_refit.refine.max_corner_shift_px = x;
    else if (k == "cref_maxblur") o.code_refit.refine.max_blur_cells = x;
    else if (k == "bent_kink") o.bent.min_kink_px = x;
    else if (k == "bent_pre") o.bent.precheck_fraction = x;
    else if (k == "bent_side") o.bent.min_side_px = x;
    else if (k == "bent_fold") o.bent.kink.max_fold_offset = x;
    else if (k == "occl") o.threshold_quads.fit.tolerate_occlusion = x != 0;
    else if (k == "refit") o.occlusion_refit = x != 0;
    else if (k == "agree") o.occlusion.agree_fraction = x;
    else if (k == "outer") o.threshold_quads.fit.refit_outer_outline = x != 0;
    else if (k == "outer_bins") o.threshold_quads.fit.outer.bins = static_cast<int>(x);
    else if (k == "outer_tol") o.threshold_quads.fit.outer.tolerance = x;
    else if (k == "outer_drop") o.threshold_quads.fit.outer.min_dropped = x;
    else if (k == "outer_max") o.threshold_quads.fit.outer.max_size_px = x;
    else if (k == "outer_ring") o.threshold_quads.fit.outer.ring_check = x != 0;
    else if (k == "outer_ppb") o.threshold_quads.fit.outer.min_points_per_box_px = x;
    else if (k == "inner") o.threshold_quads.fit.outer.innermost = x != 0;
    else if (k == "inner_cov") o.threshold_quads.fit.outer.innermost_min_coverage = x;
    else if (k == "ring_share") o.threshold_quads.fit.outer.ring_min_share = x;
    else if (k == "ring_step") o.threshold_quads.fit.outer.ring_min_step = x;
    else if (k == "ring_ratio") o.threshold_quads.fit.outer.min_side_ratio = x;
    else if (k == "ring_slack") o.threshold_quads.fit.outer.ring_outward_slack = x;
    else if (k == "ring_slack_sides") o.threshold_quads.fit.outer.ring_slack_sides = static_cast<int>(x);
    else if (k == "look") o.second_look.enabled = x != 0;
    else if (k == "look_max") o.second_look.max_size_px = x;
    else if (k == "look_min") o.second_look.min_size_px = x;
    else if (k == "look_half") o.second_look.at_half_resolution = x != 0;
    else if (k == "look_inside") o.second_look.inside_only = x != 0;
    else if (k == "look_gap") o.second_look.min_class_gap = x;
    else if (k == "look_skiprej") o.second_look.skip_border_rejected = x != 0;
    else if (k == "outer_half") o.threshold_quads.fit.outer.at_half_resolution = x != 0;
    else if (k == "soft") o.soft_decode.enabled = x != 0;
    else if (k == "soft_d1") o.soft_decode.max_distance = x;
    else if (k == "soft_gap") o.soft_decode.min_gap = x;
    else if (k == "soft_bits") o.soft_decode.max_bit_errors = static_cast<int>(x);
    else if (k == "soft_h") o.soft_decode.min_family_hamming = static_cast<int>(x);
    else if (k == "glook") o.group_look.enabled = x != 0;
    else if (k == "glook_min") o.group_look.min_size_px = x;
    else if (k == "glook_max") o.group_look.max_size_px = x;
    else if (k == "glook_pts") o.group_look.min_points = static_cast<int>(x);
    else if (k == "glook_win") o.group_look.min_window_px = x;
    else if (k == "glook_n") o.group_look.max_windows = static_cast<int>(x);
    else if (k == "lowc") o.threshold_quads.low_contrast.enabled = x != 0;
    else if (k == "self") o.payload_area.self_threshold.enabled = x != 0;
    else if (k == "self_ring") o.payload_area.self_threshold.max_light_black_ring = x;
    else if (k == "self_spare") o.payload_area.self_threshold.spare_bits = static_cast<int>(x);
    else if (k == "self_h") o.payload_area.self_threshold.min_family_hamming = static_cast<int>(x);
    else if (k == "psq") o.printed_square.enabled = x != 0;
    else if (k == "rq") o.ring_quads.enabled = x != 0;
    else if (k == "dq") o.dark_outlines.enabled = x != 0;
    else if (k == "dq_min") o.dark_outlines.min_size_px = x;
    else if (k == "dq_max") o.dark_outlines.max_size_px = x;
    else if (k == "dq_groups") o.dark_outlines.max_groups = static_cast<int>(x);
    else if (k == "dq_ring") o.dark_outlines.ring_check = x != 0;
    else if (k == "dq_overlap") o.dark_outlines.overlap_clusters = x != 0;
    else if (k == "dq_oring") o.dark_outlines.overlap_ring_check = x != 0;
    else if (k == "dq_pairs") o.dark_outlines.failed_pairs = x != 0;
    else if (k == "dq_ppts") o.dark_outlines.pair_min_points = static_cast<int>(x);
    else if (k == "dq_pshare") o.dark_outlines.pair_min_share = x;
    else if (k == "dq_pmargin") o.dark_outlines.pair_margin_px = x;
    else if (k == "dq_light") o.dark_outlines.by_light = x != 0;
    else if (k == "dq_outline") o.dark_outlines.outline_only = x != 0;
    else if (k == "dq_check") o.dark_outlines.check_before_refining = x != 0;
    else if (k == "dq_slack") o.dark_outlines.slack_sides = static_cast<int>(x);
    else if (k == "rchk") o.threshold_quads.refine_check.enabled = x != 0;
    else if (k == "coarse") o.coarse_pass.enabled = x != 0;
    else if (k == "coarse_contrast") o.coarse_pass.min_contrast = static_cast<float>(x);
    else if (k == "coarse_lowc") o.coarse_pass.low_contrast = x != 0;
    else if (k == "coarse_occl") o.coarse_pass.occlusion_fit = x != 0;
    else if (k == "coarse_minw") o.coarse_pass.min_tag_px = x;
    else if (k == "lq") o.line_quads.enabled = x != 0;
    else if (k == "lq_max") o.line_quads.max_side_px = x;
    else if (k == "lq_rb") o.line_quads.refine_black = x != 0;
    else if (k == "lq_spare") o.line_quads.spare_bits = static_cast<int>(x);
    else if (k == "lq_exact") o.line_quads.keep_exact = x != 0;
    else if (k == "overlap") o.suppress_overlaps = x != 0;
    else if (k == "refine_cells") o.threshold_quads.refine.cells_across = static_cast<int>(x);
    else if (k == "lq_check") o.line_quads.check_before_refining = x != 0;
    else if (k == "lq_slack") o.line_quads.inner_check_slack = x != 0;
    else if (k == "lq_ri") o.line_quads.refine_inner = x != 0;
    else if (k == "ls_sigma") o.line_quads.segments.sigma = x;
    else if (k == "ls_tau") o.line_quads.segments.angle_tolerance_deg = x;
    else if (k == "ls_grad") o.line_quads.segments.min_gradient = x;
    else if (k == "ls_dens") o.line_quads.segments.min_density = x;
    else if (k == "ls_eps") o.line_quads.segments.log_eps = x;
    else if (k == "ls_seed") o.line_quads.segments.min_seed_gradient = x;
    else if (k == "ls_cap") o.line_quads.segments.max_region_pixels = static_cast<int>(x);
    else if (k == "lq_scale") o.line_quads.scale = x;
    else if (k == "ls_straight") o.line_quads.segments.straight_sides = static_cast<int>(x);
    else if (k == "ls_reach") o.line_quads.segments.straight_check_px = x;
    else if (k == "ls_sseed") o.line_quads.segments.straight_seeds_only = x != 0;
    else if (k == "ls_cuts") o.line_quads.segments.max_cuts = static_cast<int>(x);
    else if (k == "rq_min") o.ring_quads.min_size_px = x;
    else if (k == "rq_max") o.ring_quads.max_size_px = x;
    else if (k == "rq_hole") o.ring_quads.min_hole = x;
    else if (k == "rq_fill") o.ring_quads.max_fill = x;
    else if (k == "psq_refine") o.printed_square.refine_edges = x != 0;
    else if (k == "cc") o.corner_completion.enabled = x != 0;
    else if (k == "cc_min") o.corner_completion.min_side_px = x;
    else if (k == "cc_max") o.corner_completion.max_side_px = x;
    else if (k == "cc_move") o.corner_completion.min_move_px = x;
    else if (k == "cc_rej") o.corner_completion.border_rejected = x != 0;
    else if (k == "cc_spare") o.corner_completion.spare_bits = static_cast<int>(x);
    else if (k == "cc_n") o.corner_completion.support_samples = static_cast<int>(x);
    else if (k == "cc_support") o.corner_completion.min_support = x;
    else if (k == "cc_contrast") o.corner_completion.min_contrast = x;
    else if (k == "lowc_contrast") o.threshold_quads.low_contrast.min_contrast = static_cast<float>(x);
    else if (k == "lowc_max") o.threshold_quads.low_contrast.max_size_px = x;
    else if (k == "lowc_ring") o.threshold_quads.low_contrast.ring_check = x != 0;
    else if (k == "lowc_min") o.threshold_quads.low_contrast.min_size_px = x;
    else if (k == "lowc_margin") o.threshold_quads.low_contrast.margin_px = x;
    else if (k == "lowc_fill") o.threshold_quads.low_contrast.min_fill = x;
    else if (k == "lowc_area") o.threshold_quads.low_contrast.min_area_px = x;
    else if (k == "lowc_occl") o.threshold_quads.low_contrast.occlusion_fit = x != 0;
    else if (k == "lowc_outer") o.threshold_quads.low_contrast.outer_outline = x != 0;
    else if (k == "lowc_aspect") o.threshold_quads.low_contrast.min_aspect = x;
    else if (k == "lowc_half") o.threshold_quads.low_contrast.at_half_resolution = x != 0;
    else throw std::invalid_argument("detector '" + name + "': unknown variant key '" + k + "'");
  }
}

DetectorOptions detector_options_from_args(std::span<char* const> args) {
  std::string spec;
  for (const char* a : args) {
    if (!spec.empty()) spec += '/';
    spec += a;
  }
  DetectorOptions o;
  apply_detector_variant(o, spec, "tagbench/" + spec);
  return o;
}

}  // namespace tagbench::bench
