#include <gtest/gtest.h>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/photometric_guard.hpp"
#include "detect/occlusion_refit.hpp"
#include "synthetic_folded.hpp"
#include "synthetic_occluded.hpp"
#include "synthetic_tag.hpp"

namespace test_photometric_guard {

using namespace tagbench;

// Flat and lightly blurred: the photometric model fits. Folded, or blurred by 2 px: it does not.
TEST(PhotometricGuard, PassesFlatTagsOnly) {
  const TagFamily& f = builtin_family("36h11");
  const PhotometricGuardOptions g;
  const Corners c = synth::square_tag_corners(60.3, 59.1, 64, 0.25);
  const ImageF flat = synth::render_tag(120, 120, tag_cells(f, 2), synth::homography_for(c));
  EXPECT_TRUE(photometric_model_fits(gaussian_blur(flat, 0.6), c, 8, g));
  EXPECT_FALSE(photometric_model_fits(gaussian_blur(flat, 2.0), c, 8, g));
  const synth::FoldedTag t = synth::folded_square(60.4, 60.2, 64, 1.0, 1.0);
  const ImageF bent = gaussian_blur(synth::render_folded(120, 120, tag_cells(f, 2), t), 0.6);
  EXPECT_FALSE(photometric_model_fits(bent, t.corners, 8, g));
  // Short sides are not judged: the same tag shrunk below min_side_px passes on its kink.
  PhotometricGuardOptions small = g;
  small.min_side_px = 100;
  EXPECT_TRUE(photometric_model_fits(bent, t.corners, 8, small));
}

// The guarded refinement leaves a folded tag's corners as they were, refines a flat one's, and with
// the guard off is refine_detections_photometric.
TEST(PhotometricGuard, GuardedRefinementSkipsOnlyWhatTheGuardRefuses) {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  const Corners truth = synth::square_tag_corners(60.3, 59.1, 64, 0.25);
  const ImageF flat = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, 2), synth::homography_for(truth)), 0.6);
  Detection d;
  d.family = "36h11";
  d.id = 2;
  d.corners = synth::perturbed(truth, 0.2, 7);
  std::vector<Detection> guarded{d}, plain{d};
  refine_detections_photometric_guarded(guarded, flat, fams, PhotometricRefineOptions{}, PhotometricGuardOptions{});
  refine_detections_photometric(plain, flat, fams, PhotometricRefineOptions{});
  EXPECT_LT(synth::corner_rms(guarded[0].corners, truth), 0.03);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(guarded[0].corners[i], plain[0].corners[i]);

  const synth::FoldedTag t = synth::folded_square(60.4, 60.2, 64, 1.0, 1.0);
  const ImageF bent = gaussian_blur(synth::render_folded(120, 120, tag_cells(f, 2), t), 0.6);
  d.corners = t.corners;
  std::vector<Detection> b{d}, off{d};
  refine_detections_photometric_guarded(b, bent, fams, PhotometricRefineOptions{}, PhotometricGuardOptions{});
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(b[0].corners[i], t.corners[i]);
  PhotometricGuardOptions disabled;
  disabled.enabled = false;
  std::vector<Detection> ref{d};
  refine_detections_photometric_guarded(off, bent, fams, PhotometricRefineOptions{}, disabled);
  refine_detections_photometric(ref, bent, fams, PhotometricRefineOptions{});
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(off[0].corners[i], ref[0].corners[i]);
}

// An occluded tag (the bottom border edge covered over its middle, as raytrace conditions renders
// it): the occlusion refit reports the hidden part of the bottom side; the guard does not read the
// occluder's edge as a bend, and the refinement leaves the hidden part out. Without the mask the
// Huber-weighted occluder pulls the fit off the truth; without skip_hidden_sides the guard refuses.
TEST(PhotometricGuard, OccludedTagIsRefinedWithoutItsHiddenPart) {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  const Corners truth = synth::square_tag_corners(100.3, 95.6, 64, 0.45);
  const ImageF img = gaussian_blur(synth::occluded_tag(truth, 0.6, 200, 190), 0.6);
  const OcclusionRefitResult r = refit_occluded_sides(img, synth::perturbed(truth, 0.15, 3), 8);
  ASSERT_TRUE(r.corners);
  ASSERT_FALSE(r.hidden[0] || r.hidden[1] || r.hidden[3]);
  ASSERT_TRUE(r.hidden[2]);  // BR -> BL: the occluder covers the middle 60 %
  EXPECT_NEAR((*r.hidden[2])[0], 0.2, 0.1);
  EXPECT_NEAR((*r.hidden[2])[1], 0.8, 0.1);
  const std::vector<HiddenSides> hidden{r.hidden};

  Detection d;
  d.family = "36h11";
  d.id = 7;
  d.corners = *r.corners;
  const PhotometricGuardOptions g;
  EXPECT_TRUE(photometric_model_fits(img, d.corners, 8, g, r.hidden));
  PhotometricGuardOptions judged = g;
  judged.skip_hidden_sides = false;
  EXPECT_FALSE(photometric_model_fits(img, d.corners, 8, judged, r.hidden));

  std::vector<Detection> masked{d}, unmasked{d};
  refine_detections_photometric_guarded(masked, img, fams, PhotometricRefineOptions{}, g, hidden);
  PhotometricGuardOptions no_mask = g;
  no_mask.hidden_depth_cells = 0;
  refine_detections_photometric_guarded(unmasked, img, fams, PhotometricRefineOptions{}, no_mask, hidden);
  const double e_masked = synth::corner_rms(masked[0].corners, truth), e_unmasked = synth::corner_rms(unmasked[0].corners, truth);
  EXPECT_LT(e_masked, 0.03);
  EXPECT_LT(e_masked, 0.5 * e_unmasked) << e_masked << " vs " << e_unmasked;
}

// align_tag_scale undoes a similarity of the tag plane (scale about the centre, shift) exactly.
TEST(PhotometricGuard, AlignTagScaleRecoversASimilarityOfTheTagPlane) {
  const Corners c = synth::square_tag_corners(60.3, 59.1, 64, 0.25);
  Corners skewed = c;
  skewed[2] += Eigen::Vector2d(3, 1);  // a perspective view, not a square
  const Eigen::Matrix3d H = synth::homography_for(skewed);
  const std::array<Eigen::Vector2d, 4> u{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                                         Eigen::Vector2d(-1, 1)};
  Corners scaled;
  for (std::size_t i = 0; i < 4; ++i) scaled[i] = apply_homography(H, 1.04 * u[i] + Eigen::Vector2d(0.02, -0.01));
  const auto a = align_tag_scale(scaled, skewed);
  ASSERT_TRUE(a);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_LT(((*a)[i] - skewed[i]).norm(), 1e-6);
}

// A heavily blurred tag (median edge blur above keep_scale_min_blur_px) is refined and the result
// scaled onto the edge-refined corners; with blurred_keep_scale off it keeps its corners.
TEST(PhotometricGuard, HeavilyBlurredTagIsRefinedThenScaledOntoTheEdgeCorners) {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  const Corners truth = synth::square_tag_corners(70.3, 69.1, 80, 0.25);
  const ImageF img = gaussian_blur(synth::render_tag(140, 140, tag_cells(f, 2), synth::homography_for(truth)), 2.4);
  BorderKinkOptions k = PhotometricGuardOptions::flat_kink_options();
  const auto sides = measure_border_kinks(img, truth, k);
  ASSERT_TRUE(sides);
  ASSERT_GT(median_blur_px(*sides), PhotometricGuardOptions{}.keep_scale_min_blur_px);
  Detection d;
  d.family = "36h11";
  d.id = 2;
  d.corners = synth::perturbed(truth, 0.15, 5);
  std::vector<Detection> on{d}, off{d};
  const PhotometricGuardOptions g;
  refine_detections_photometric_guarded(on, img, fams, PhotometricRefineOptions{}, g);
  PhotometricGuardOptions keep = g;
  keep.blurred_keep_scale = false;
  refine_detections_photometric_guarded(off, img, fams, PhotometricRefineOptions{}, keep);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(off[0].corners[i], d.corners[i]);
  EXPECT_GT(synth::corner_rms(on[0].corners, d.corners), 1e-3);
  EXPECT_LT(synth::corner_rms(on[0].corners, truth), synth::corner_rms(d.corners, truth));
}

}  // namespace test_photometric_guard
