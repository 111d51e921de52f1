#pragma once
// The detector's options (detector.hpp): which quad finder and payload reader, every stage's options
// with its documented default, and the three profiles (DetectorOptions{} the default profile,
// paper() sections III-IV exactly, thorough() the default with full-resolution line quads and the
// coarse pass). validate() (in
// detector_options.cpp) names the first field out of range. Units and conventions as detector.hpp.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "../codes/tag_family.hpp"
#include "line_fit.hpp"
#include "occlusion_refit.hpp"
#include "payload_area.hpp"
#include "payload_decode.hpp"
#include "bent_decode.hpp"
#include "code_refit.hpp"
#include "corner_completion.hpp"
#include "defocus_read.hpp"
#include "photometric_guard.hpp"
#include "pose_choice.hpp"
#include "printed_square.hpp"
#include "ring_quads.hpp"
#include "line_quads.hpp"
#include "linear_corners.hpp"
#include "coarse_pass.hpp"
#include "dark_outlines.hpp"
#include "photometric_refine.hpp"
#include "pose.hpp"
#include "quad_search.hpp"
#include "group_look.hpp"
#include "second_look.hpp"
#include "segmentation.hpp"
#include "soft_decode.hpp"
#include "threshold_quads.hpp"

namespace tagbench {

// Which function finds the candidate quads (stages 1-5; the Detector's QuadFinder).
enum class QuadFinderKind {
  kGradient,   // the paper's: blur, gradients, clusters, segments, quads (find_quads_in_image.hpp)
  kThreshold,  // beyond the paper: adaptive threshold, components, boundaries, quad fit, edge
               // refinement (find_threshold_quads_in_image.hpp)
};

// How each payload cell is read (stage 6).
enum class PayloadReaderKind {
  kPoint,  // the paper's: one bilinear sample at the cell centre (read_payload, payload_decode.hpp)
  kArea,   // beyond the paper: k x k samples over the cell, optional sharpening (read_payload_area,
           // payload_area.hpp); min_contrast is PayloadOptions::min_contrast
};

// The threshold quad finder's options in the default profile: occluded tags are fitted too, and a
// group whose fit fails (or leaves out much of it) is fitted again on its outer outline
// (fit.refit_outer_outline, outer_outline.hpp), only for groups up to 80 px across, only keeping
// outline quads with a lighter ring around a darker border on every sample of every side
// (outer.ring_check, ring_min_share 1: 0.75 let 16h5 false detections on the corpus rise 0.075 ->
// 0.21 per image, 1 gives 0.12 for 4 fewer realistic tags of 929) and not at half resolution
// (outer.at_half_resolution). Realistic set (200 frames): 20-24 px tags 123 -> 134 of 188, all sizes
// 883 -> 925 of 1384; time / libapriltag d1 about 0.54 -> 0.66 on the corpus (issue 17, session 7).
// 50 px until session 20: a 20 px tag's group often holds its plate (up to 3 cells round the tag) and
// texture touching it, and with the points-per-length gate below the larger groups cost little.
inline ThresholdQuadOptions default_profile_threshold_quads() {
  ThresholdQuadOptions q;
  q.fit.tolerate_occlusion = true;
  q.fit.refit_outer_outline = true;
  // Up to 80 px (session 20, with the innermost outline below; realistic seeds 1, 2, 3, 200 frames):
  // 1015 -> 1022, 980 -> 985, 1066 -> 1074 tags (20-24 px +1, +1, 0), none lost, no wrong id, +1.7 %
  // time on realistic frames and +2.5 % on the corpus; 16h5 false detections on the corpus 157 -> 160
  // of 1182 images; sweeps: the same detections (one angle and one 6-DoF row take their corners from
  // another candidate).
  q.fit.outer.max_size_px = 80;
  q.fit.outer.ring_check = true;
  q.fit.outer.ring_min_share = 1.0;
  // Only groups with at least 4 boundary points per px of their box's width plus height (one plain
  // outline gives about 4; session 19): of 71 k groups tried on 100 realistic frames, 27 k are left,
  // and those whose outline gave a tag held 5-14 (a tag seen at 78 degrees 5.4). Realistic seeds 1, 2,
  // 3 (200 frames): every row the same, 5.5 % less time; distance, angle, conditions and 6-DoF
  // sweeps: the same detections (21 of the 30 k distance rows, all at 40-60 m, have their corners from
  // another duplicate candidate).
  q.fit.outer.min_points_per_box_px = 4;
  // Each side's ring pairs also read 1/16 of the quad's width further out, at most one side passing
  // only so (session 36, on by default since session 37 with SoftDecodeOptions::min_opposite_ratio
  // 0.8): a blurred 1-cell border with light payload cells behind it, whose threshold outline lies a
  // pixel inside the square's edge on one side. Realistic seeds 1 / 2 (200 frames): 1100 -> 1102,
  // 1048 -> 1051 tags, 20-24 px 172 -> 173, 177 -> 179, no wrong id, no false detection, the same
  // time; linear-camera set 968 -> 968, sharpened 1100 -> 1100 (20-24 px 162 -> 161); ray-traced
  // distance, angle and conditions sweeps every detection the same; corpus 16h5 false detections
  // 295 -> 337 (of 1182 images; libapriltag d2 about 2700), 36h11 0.
  q.fit.outer.ring_outward_slack = 1.0 / 16;
  q.fit.outer.ring_slack_sides = 1;
  // Where the outermost outline gives no quad, the innermost outward outline (outer_outline.hpp; session
  // 20): a tag whose border ran through a broken white ring into a darker plate. Realistic seeds 1, 2,
  // 3 (200 frames each): 1014 -> 1015, 974 -> 980, 1065 -> 1066 tags (20-24 px: 159 -> 160, 160 -> 164,
  // 198), none lost, no wrong id; +0.5 % time; the sweeps identical; 16h5 false detections on the
  // corpus 156 -> 157 of 1182 images.
  q.fit.outer.innermost = true;
  // The low-contrast look (low_contrast_quads.hpp; issue 17, session 9): faint small tags the 20/255
  // floor leaves unknown. Realistic set (200 frames): 20-24 px tags 146 -> 153 of 188, all sizes
  // 970 -> 988 of 1384, no wrong id, no tag lost; time / libapriltag d1 0.76 -> 0.84-0.87 on the
  // realistic set (100 frames, +9-14 % over two runs) and 0.72 -> 0.79 on the corpus (1182 images,
  // +10 %); 16h5 false detections 0.141 -> 0.142 per corpus image. Not at half resolution.
  q.low_contrast.enabled = true;
  // Regions up to 64 px (+ 2 windows; 48 until session 20, measured together with the second look up
  // to 80 px: see default_profile_second_look).
  q.low_contrast.max_size_px = 64;
  // Quads the decoder's border pre-filter will refuse are not refined first (session 27): realistic
  // seeds 1 and 2 (200 frames) the same tags (one corner from another duplicate quad), about 3 % less
  // time.
  q.refine_check.enabled = true;
  return q;
}

// The line quads' options in the default profile (DetectorOptions::line_quads; session 27): the
// edges found on the 2 x 2-averaged image, from seeds with aligned pixels 3 px along their edge on
// both sides (segments.straight_seeds_only, straight_sides 2), each quad's border pre-filtered before
// it is refined, and not at half resolution. In place of the coarse pass, with the joined outlines
// (dark_outlines), on the realistic set (200 frames, seeds 1 / 2 / 3, a holdout): 1059 -> 1098,
// 1035 -> 1046, 1132 -> 1147 tags; 20-24 px 165 -> 170 of 188, 173 -> 176 of 214, 210 -> 212 of 251;
// no wrong id; about 9 % more time there (docs/default-profile.md, session 27).
inline LineQuadOptions default_profile_line_quads() {
  LineQuadOptions o;
  o.enabled = true;
  o.scale = 0.5;
  o.segments.straight_seeds_only = true;
  o.segments.straight_sides = 2;
  o.check_before_refining = true;
  o.inner_check_slack = true;  // session 29
  o.at_half_resolution = false;
  return o;
}

// The second look's options in the default profile (DetectorOptions::second_look).
inline SecondLookOptions default_profile_second_look() {
  SecondLookOptions o;
  o.enabled = true;
  // Up to 80 px (64 until session 20; realistic seeds 1, 2, 3, 200 frames, with the low-contrast
  // look's regions up to 64 px: 1022 -> 1026, 985 -> 995, 1074 -> 1080 tags, none lost, no wrong id;
  // +2.2 % time on realistic frames, +1.3 % on the corpus; sweeps and 16h5 false detections the same).
  o.max_size_px = 80;
  o.min_size_px = 16;
  o.skip_border_rejected = true;  // session 29: its time pays for the line quads' inner_check_slack
  return o;
}

// The most bits any option may ask a decoder to correct (DetectorOptions::max_hamming's ceiling).
inline constexpr int kMaxBitsCorrected = 16;

// The bits a family of minimum Hamming distance h corrects: min(max_hamming, (h - 1) / 3) when
// hamming_by_family (DetectorOptions::hamming_by_family), else max_hamming.
inline int bits_corrected_for(int min_hamming, int max_hamming, bool hamming_by_family) {
  const int cap = min_hamming > 1 ? (min_hamming - 1) / 3 : 0;
  return hamming_by_family ? (max_hamming < cap ? max_hamming : cap) : max_hamming;
}

// Three profiles. The default member values are the DEFAULT profile, what the library and `tagbench
// detect` use unless told otherwise: the threshold quad finder with edge refinement, the area
// payload reader and the photometric corner refinement (chosen by measurement, README "Default
// profile"). DetectorOptions::paper() is the paper's detector (sections III-IV) exactly as the
// reproduction of its experiments uses it. DetectorOptions::thorough() is the default profile with
// the line quads (line_quads.hpp) on the full-resolution image and the coarse pass (coarse_pass.hpp):
// more of the small, faint tags of photographs for about twice the default profile's time (README,
// "The thorough profile").
struct DetectorOptions {
  // The paper's detector: the gradient quad finder and point payload reading, no photometric
  // refinement, every other field at
  // its default (which is the paper's value, or off for the additions that keep the paper's
  // results). Every paper experiment (Figs. 6, 7, 9, 10; tagbench-paper in the comparisons) uses it.
  static DetectorOptions paper();
  // The default profile with quads from straight edges found on the full-resolution image
  // (line_quads with LineQuadOptions' own defaults: scale 1, every seed, refined before reading):
  // on the realistic set, 20-24 px tags 87 % -> 94 %, at 2.1 x the default profile's time of session
  // 24 (docs/default-profile.md, sessions 22-24); and the coarse pass (coarse_pass.enabled), which the
  // default profile gave up for its half-size line quads in session 27. The edges are found at full
  // resolution whatever half_resolution says: with it, only the threshold stage runs at half size.
  static DetectorOptions thorough();
  // A profile by its name, as the command line and Python name it: "default" (DetectorOptions{}),
  // "thorough" or "paper"; nullopt for any other name.
  static std::optional<DetectorOptions> named_profile(std::string_view name);

  std::vector<std::string> families = {"36h11"};  // built-in names or family files
  // Bits corrected at most (paper(): 1, the Java default; docs/paper-to-code.md section 1). Default
  // profile: 3, each family capped by hamming_by_family.
  int max_hamming = 3;
  // Beyond the paper: a family of minimum Hamming distance h corrects at most min(max_hamming,
  // floor((h - 1) / 3)) bits (36h11 and 36h10 3, 25h9 2, 16h5 1): a word accepted k bits from a code
  // is then at least 2k + 1 bits from every other code, so a misread tag is far likelier to be
  // refused than taken for another id, and small families (16h5) keep few false detections. On the
  // distance sweep 36h11 then reads 10-9 px tags whose 1.2 px cells blur into 2-3 wrong bits (README
  // "Default profile"). Default profile on; paper(): off (max_hamming for every family).
  bool hamming_by_family = true;
  // The bits corrected for a family of minimum Hamming distance h under these options.
  int bits_corrected(int min_hamming) const;
  // Default profile: candidate quads from the threshold stage (paper(): kGradient).
  QuadFinderKind quad_finder = QuadFinderKind::kThreshold;
  // Options of the threshold quad finder (quad_finder = kThreshold); its `halve` is ignored:
  // half_resolution below says whether the threshold runs on the half-size image. Default profile:
  // ThresholdQuadOptions' defaults plus fit.tolerate_occlusion (quad_fit_occluded.hpp).
  ThresholdQuadOptions threshold_quads = default_profile_threshold_quads();
  // Default profile: payload cells read over their area (paper(): kPoint).
  PayloadReaderKind payload_reader = PayloadReaderKind::kArea;
  PayloadAreaOptions payload_area;  // for kArea; its min_contrast is ignored (payload.min_contrast is used)
  // Beyond the paper: drop detections whose decision_margin (payload_decode.hpp) is below this, in
  // [0, 1]; 0 keeps every one (the paper's detector). Applied to the final detections, after
  // duplicates are merged (and overlaps, suppress_overlaps below), so a run at 0 whose detections are
  // then filtered at m gives exactly what a run at m gives (how `tagbench falsepos margin` scores
  // thresholds from one run). What each
  // threshold saves in false detections and costs in real ones: results/margin_tradeoff.csv (README).
  double min_decision_margin = 0;
  // Beyond the paper: of two detections of different ids over the same quad, only the one with fewer
  // bits corrected (then the higher decision margin) is kept (suppress_duplicates.hpp), after the
  // duplicates are merged and before min_decision_margin. Default profile on (realistic set in 16h5:
  // every wrong id was such a second reading beside the right one); paper(): off.
  bool suppress_overlaps = true;
  // The encoding gamma of the input's intensities (value = linear^(1 / input_gamma)): 2.2 for
  // gamma-encoded images (sRGB: camera JPEGs and PNGs, most 8-bit images), 1 for linear ones
  // (renders written with gamma 1, as the ray-traced sweeps' frames are; raw sensor data, linear
  // machine-vision cameras). Used where an edge's position is measured on a decoded tag
  // (linear_corners, the occlusion refit, the photometric refinement); which tags are decoded does not
  // depend on it (the occlusion refit, judging sides so placed, may withdraw another few). In [0.1, 10].
  // Default 1 (the image as it is) because a wrong gamma costs far more than the right one gains
  // (realistic set, 200 frames, median / 90th percentile corner RMS): sRGB frames read as 1 instead of
  // 2.2: 0.108 / 0.497 px instead of 0.103 / 0.471; frames of a linear camera read as 2.2 instead of 1:
  // 0.185 / 0.732 px instead of 0.100 / 0.348 (docs/default-profile.md, session 33).
  double input_gamma = 1.0;
  // Beyond the paper: the decoded tags' sides located again on linear intensities (input_gamma;
  // linear_corners.hpp), after min_decision_margin and before the occlusion refit. Default profile
  // on; paper(): off.
  LinearCornerOptions linear_corners;
  // Beyond the paper: after decoding, check each side against the decoded tag (black ring inside,
  // white ring outside), re-fit a partly occluded side from its visible part, withdraw the detection
  // when a side cannot be fixed (occlusion_refit.hpp). Default profile on; paper(): off.
  bool occlusion_refit = true;
  OcclusionRefitOptions occlusion;
  // Beyond the paper: threshold quads up to 64 px that did not decode are looked at again, their
  // region classed by one (Otsu) threshold from the pixels inside the quad and fitted anew
  // (second_look.hpp; quad_finder kThreshold only; not at half resolution, second_look.at_half_resolution).
  // Default profile on; paper(): off. Realistic set
  // (200 frames, seed 1): 20-24 px tags 134 -> 146 of 188, all sizes 925 -> 970 of 1384, no wrong id;
  // time / libapriltag d1 on 300 corpus images 0.64 -> 0.69 (issue 17, session 8).
  SecondLookOptions second_look = default_profile_second_look();
  // Beyond the paper: boundary groups of tag size that gave no quad, each a window classed by one
  // (Otsu) threshold and fitted anew like the second look (group_look.hpp; quad_finder kThreshold,
  // full resolution only; uses second_look's min_class_gap, min_corner_change_px). paper(): off, and
  // off in the default profile too (issue 17, session 10): realistic set (200 frames, seed 1) 20-24 px
  // 156 -> 156 of 188, all sizes 1005 -> 1009 of 1384 (1011 with windows up to 64 px, min_window_px 40),
  // no wrong id, no false detection. Not worth its cost: even a window centred on the TRUE tag (1.6 x
  // its size) classed by one Otsu threshold yields a matching quad for 19 of the 164 readable tags
  // without a candidate, 0 of the 20 at 20-24 px (1 with a 1 px blur first): at those contrasts no
  // single threshold gives the square's outline (bench/experiments/candidate_loss, session 10).
  GroupLookOptions group_look;
  // Beyond the paper: the threshold stage again on the half-size image with a lower contrast floor,
  // for larger tags of low contrast; its quads that no tag found so far covers are decoded after
  // the second look (coarse_pass.hpp; quad_finder kThreshold, full resolution only). On in
  // thorough(); off in paper() and, since session 27, in the default profile, whose half-size line
  // quads and joined outlines find more for its time (docs/default-profile.md). Realistic set (200
  // frames, session 25): seed 1 1045 -> 1059 of 1384 tags (20-24 px 164 -> 165 of 188), seed 2
  // 1013 -> 1035 (170 -> 173 of 214), none lost, no wrong id; about 20 % more time there and on the
  // corpus (issue 17, session 25).
  CoarsePassOptions coarse_pass;
  // Beyond the paper: the boundary groups that share a dark (or a light) component joined into one
  // outline and fitted again (dark_outlines.hpp; quad_finder kThreshold, full resolution only), for
  // small tags whose white ring or border broke into pieces. On in the default profile (since session
  // 27, with the half-size line quads in place of the coarse pass) and thorough(); paper(): off. Alone
  // in the default of session 26: +19 tags of 1384 on seed 1 for 13 % more time (docs/default-profile.md).
  // Its quads pass the border pre-filter (3 of 4 sides with slack) before they are refined (session
  // 30): realistic seeds 1 / 2 / 3 the same 1100 / 1049 / 1149 tags, 0.983 x the time.
  DarkOutlineOptions dark_outlines{.enabled = true, .check_before_refining = true, .slack_sides = 3};
  // Beyond the paper: each threshold quad that did not decode is also read as a printed square (the
  // white ring classed with the border): the black square inside it is a further candidate
  // (printed_square.hpp; quad_finder kThreshold). Default profile on; paper(): off.
  PrintedSquareOptions printed_square{.enabled = true};
  // Beyond the paper: white rings on a darker card (light-inside boundary groups of tag size) fitted
  // as quads and read as printed squares (ring_quads.hpp; quad_finder kThreshold, full resolution
  // only; the tags found refined when printed_square.refine_edges). Default profile on; paper(): off.
  RingQuadOptions ring_quads{.enabled = true};
  // Beyond the paper: quads of straight edges (line_segments.hpp, LSD's method) where no tag was
  // found, read as black squares and as printed squares (line_quads.hpp; quad_finder kThreshold).
  // Default profile: the edges of the half-size image, cheaper seeds (default_profile_line_quads);
  // thorough(): the full-resolution image, whose edge pass costs about as much as the rest of the
  // detector (docs/default-profile.md, sessions 22-27); paper(): off.
  LineQuadOptions line_quads = default_profile_line_quads();
  // Beyond the paper: a quad whose reading no family decodes within its corrected bits is decoded
  // soft (soft_decode.hpp): the codeword likeliest under the cells' signed confidences, accepted only
  // by a likelihood-ratio rule calibrated to give no false detection of 36h11 on the corpus, and only
  // for families of minimum Hamming distance >= soft_decode.min_family_hamming (10: 36h11, 36h10). Applies to
  // decode_quads' quads (first pass and second look). Default profile on; paper(): off.
  SoftDecodeOptions soft_decode;
  double seg_sigma = 0.8;        // the paper's sigma: blur before segmentation
  double decode_sigma = 0.0;     // optional separate blur of the image the payload is read from (0 = off)
  bool half_resolution = false;  // find quads at half resolution (the paper's "4x faster" option; both finders)
  SegmentationOptions segmentation;  // K_D, K_M, minMag, ...
  LineFitOptions line_fit;
  QuadSearchOptions quad_search;
  PayloadOptions payload;
  // Beyond the paper: the decoded tags' corners refined against their known printed pattern on the
  // unblurred image (photometric_refine.hpp), before the poses. Default profile: on (paper(): off).
  PhotometricRefineOptions photometric;
  // Beyond the paper: the photometric refinement skipped on a bent or heavily blurred tag, where its
  // one-homography model fits worse than the edge-refined corners (photometric_guard.hpp). Default
  // profile: on; it only acts where photometric.enabled.
  PhotometricGuardOptions photometric_guard;
  // Beyond the paper: a quad read but not decoded gets a second reading as a tag folded along a
  // centre line when its border shows two opposite sides bent (bent_decode.hpp). Default profile:
  // on (paper(): off).
  BentReadOptions bent;
  // Beyond the paper: a quad read but decoded by no family, when the likeliest code of a family of
  // large minimum distance is within code_refit.max_bits of its reading with only weak cells
  // disagreeing, is placed by that code's printed pattern (photometric refinement) and read again;
  // kept only when the new reading decodes to that code (code_refit.hpp). Runs after the second look,
  // on every quad still undecoded. Default profile on; paper(): off. Realistic set (200 frames, seed
  // 1): 20-24 px 156 -> 159 of 188, all sizes 1005 -> 1014 of 1384, no wrong id (issue 17, sessions 15-16).
  CodeRefitOptions code_refit;
  // Beyond the paper: a small quad still undecoded after the code refit read again through a model
  // of a lens's disk defocus, placed by the likeliest code's blurred pattern (defocus_read.hpp).
  // Default profile on; paper(): off. Realistic set (200 frames): seed 1 1102 -> 1110 tags, seed 2
  // 1051 -> 1062, under a disk defocus (100 frames) 493 -> 504; no wrong id, no false detection,
  // none on the corpus in 36h11 (docs/default-profile.md, session 43).
  DefocusReadOptions defocus_read;
  // Beyond the paper: each quad still undecoded after every other source and retry, with one corner
  // replaced by the parallelogram completion of its other three (a corner cut by a shadow's edge or
  // run into a dark neighbour), border pre-filtered, refined and read with the line quads' stricter
  // test (corner_completion.hpp). Off in every profile: realistic seeds 1 / 2 +4 / +2 tags for 5-6 %
  // more time (docs/default-profile.md, session 47).
  CornerCompletionOptions corner_completion;
  // Pose: given intrinsics (pixels) and the tag size (metres, > 0).
  std::optional<CameraIntrinsics> camera;
  std::optional<std::array<double, 5>> distortion;  // OpenCV's k1, k2, p1, p2, k3; corners are undistorted first
  double tag_size = 0;
  bool refine_pose = true;  // beyond the paper: minimise the corners' reprojection error, both ambiguity solutions
  // Beyond the paper: with refine_pose and no distortion, the ambiguity's two solutions judged on the image
  // against the decoded pattern (pose_choice.hpp). Default profile on; paper(): off.
  PoseChoiceOptions pose_choice;
  // Image-size limit (width x height pixels). detect() refuses a larger image with
  // std::invalid_argument ("image WxH (N pixels) is over the detector's limit of M pixels ...")
  // before allocating anything, so one huge input cannot exhaust memory. Detection needs about
  // 49 bytes a pixel at full resolution and 16 with half_resolution, plus a share that grows with
  // the scene's edge pixels (12-24 bytes per graph edge; 49-61 bytes a pixel in all on the
  // synthetic scenes of results/memory.csv, bench/detect_memory.cpp), and 12 (BGR) or 16 (BGRA)
  // more for colour input. So the default, 100 M pixels (10000 x 10000), means at most about
  // 5-6 GB at full resolution. The limit bounds the detector's own memory only: the caller's image
  // is not counted (OpenCV's imread has its own limit, OPENCV_IO_MAX_IMAGE_PIXELS, 2^30 by
  // default). Allowed values: 1..kMaxPixelsCeiling; the constructor refuses others.
  long long max_pixels = 100'000'000;

  // Checks every numeric field, nested options included, and throws std::invalid_argument with one
  // line naming the first bad field as it is spelt here and its value,
  // "FIELD = VALUE: RULE" (e.g. "quad_search.grid_cell = 0: must be finite and > 0"). The domains:
  //   families                non-empty, no two of one name; max_hamming 0..max(0, h - 1), h the
  //                           smallest minimum Hamming distance of the families (at h or more bits a
  //                           code's acceptance ball holds other codes of its family: nothing would be
  //                           an error any more); with hamming_by_family 0..kMaxBitsCorrected (a cap:
  //                           each family's (h - 1) / 3 is below h already);
  //   min_decision_margin     [0, 1]; seg_sigma, decode_sigma: finite, >= 0;
  //   segmentation            min_mag, k_theta, k_mag finite >= 0; max_edge_cost in (0, pi];
  //                           weight_scale 1..kMaxWeightScale; min_cluster_size >= 1;
  //   line_fit.min_length     finite >= 0;
  //   quad_search             close_enough one of the rules; min_tag_size, grid_cell finite > 0;
  //                           max_aspect finite >= 1; winding_min < winding_max, both finite; max_quads >= 1;
  //   payload.min_contrast    [0, 1];
  //   quad_finder, payload_reader  one of the enumerators;
  //   threshold_quads         blur_sigma finite >= 0; threshold.tile_size 1..256; threshold.min_contrast
  //                           [0, 1]; refine_check.payload_width 1..8, refine_check.min_contrast [0, 1];
  //                           boundaries.min_component_pixels >= 1; fit.min_points >= 4,
  //                           fit.max_maxima 4..64, fit.max_line_fit_mse finite > 0, fit.min_angle_deg
  //                           [0, 45], fit.min_tag_width finite >= 0, fit.dark_inside or light_inside;
  //   threshold_quads.low_contrast  (low_contrast_quads.hpp) min_contrast, min_fill, min_aspect [0, 1];
  //                           max_size_px finite > 0; min_size_px, min_area_px, margin_px finite >= 0;
  //   threshold_quads.fit.outer  (outer_outline.hpp) bins 8..1024; tolerance (0, 1); min_dropped,
  //                           innermost_min_coverage, ring_min_share, min_side_ratio [0, 1];
  //                           ring_outward_slack [0, 0.25]; ring_slack_sides 0..4; max_size_px > 0;
  //                           min_corner_change_px, min_points_per_box_px, ring_min_step finite >= 0;
  //   threshold_quads.refine  (edge_refine.hpp) step_px, derivative_half_px, sample_spacing_px,
  //                           range_cell_fraction, max_corner_shift_px, gamma finite > 0;
  //                           0 < min_range_px <= max_range_px, finite; end_margin [0, 0.5);
  //                           min_samples, iterations, cells_across >= 1;
  //   photometric             iterations 1..100, min_pixels >= 1, max_pixels >= min_pixels;
  //                           margin_cells [0, 1); band_px, initial_blur_px, max_corner_shift_px,
  //                           max_blur_cells finite > 0; min_black_square_px, huber, pixels_per_side_px finite >= 0;
  //                           min_contrast [0, 1];
  //   photometric_guard       max_kink_px, min_kink_significance, min_side_px, max_blur_px, hidden_depth_cells,
  //                           hidden_pad_cells, keep_scale_min_blur_px finite >= 0;
  //   pose_choice             max_alternative_rms_px, min_correlation_gain, ambiguous_correlation_gap,
  //                           gentle_max_alternative_rms_px, gentle_min_correlation_gain, gentle_model_blur_px
  //                           finite >= 0; samples_per_cell, gentle_samples_per_cell 1..16; min_view_angle_deg [0, 90];
  //                           kink as for bent.kink;
  //   bent                    min_kink_px finite >= 0; precheck_samples 4..256; precheck_fraction [0, 1];
  //                           kink.samples 4..256, kink.end_margin [0, 0.5),
  //                           kink.range_cells, kink.min_range_px, kink.step_px, kink.derivative_half_px
  //                           finite > 0, kink.max_fold_offset [0, 0.9], kink.cells_across >= 1;
  //   payload_area            samples_per_side 1..16; sample_extent [0, 1]; sharpening finite >= 0;
  //   soft_decode             max_bit_errors 0..64; max_distance, min_gap, confidence_cap finite >= 0;
  //                           min_opposite_ratio [0, 1];
  //   ring_quads              min_size_px, min_hole finite >= 0; max_size_px, max_fill finite > 0;
  //   coarse_pass             min_contrast [0, 1]; min_tag_px finite >= 0;
  //   dark_outlines           min_size_px finite >= 0, max_size_px finite > 0; 2 <= min_groups <= max_groups;
  //                           slack_sides 0..4;
  //   camera                  fx, fy in [0.01, 1e8] px, cx, cy in [0, 1e8] px; tag_size in [1e-6, 1e6] m
  //                           with a camera, finite >= 0 without; distortion only with a camera, each
  //                           coefficient in [-1e4, 1e4];
  //   max_pixels              1..kMaxPixelsCeiling.
  // validate() loads `families` (load_family, whose errors name the family) for the max_hamming
  // rule; validate(loaded) takes them already loaded, in the same order. Detector's constructor calls it.
  void validate() const;
  void validate(std::span<const TagFamily> loaded) const;
};

// Pixel indices are 32-bit in the segmentation (graph edges, union-find), so no option can raise
// the limit past 2^31 - 1 pixels.
inline constexpr long long kMaxPixelsCeiling = 2'147'483'647;

// SegmentationOptions::weight_scale's ceiling: the counting sort's histogram has weight_scale + 1
// entries per frame; 2^16 levels of direction difference are already finer than the float angles.
inline constexpr int kMaxWeightScale = 1 << 16;

}  // namespace tagbench
