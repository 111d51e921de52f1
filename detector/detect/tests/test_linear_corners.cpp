#include <gtest/gtest.h>

#include <cmath>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/edge_refine.hpp"
#include "detect/linear_corners.hpp"
#include "detect/photometric_refine.hpp"
#include "synthetic_tag.hpp"

namespace test_linear_corners {

using namespace tagbench;
using synth::corner_rms;

namespace {

// A 36h11 tag with a 24 px black square, blurred as a lens would (sigma 1 px) and then gamma-encoded
// as a camera stores it (value = linear^(1/2.2)): the black square's steps are lopsided.
struct EncodedTag {
  Corners truth;
  ImageF img;
};
EncodedTag encoded_tag(int id, double phi) {
  const TagFamily& f = builtin_family("36h11");
  EncodedTag t;
  t.truth = synth::square_tag_corners(32.3, 31.8, 24.0, phi);
  t.img = gaussian_blur(synth::render_tag(64, 64, tag_cells(f, id), synth::homography_for(t.truth), 0.6f, 8, 0.03f, 0.85f), 1.0);
  for (auto& v : t.img.data) v = std::pow(v, 1.0f / 2.2f);
  return t;
}

// A detection as the detector hands it over: the quad refined on the encoded image as it is.
Detection detection_on(const EncodedTag& t, int id) {
  Detection d;
  d.family = "36h11";
  d.id = id;
  EXPECT_TRUE(move_detection_to(d, refine_quad_edges(t.img, t.truth)));
  return d;
}

}  // namespace

// On the encoded image the refined square is smaller than the truth (0.4-0.6 px RMS here); located
// again on linear intensities its corners come back to 0.1-0.2 px, on several rotations.
TEST(LinearCorners, GammaEncodedTagsCornersComeBackToTheTruth) {
  const std::vector<TagFamily> families = {builtin_family("36h11")};
  for (int k = 0; k < 4; ++k) {
    const EncodedTag t = encoded_tag(10 + k, 0.2 + 0.4 * k);
    std::vector<Detection> d = {detection_on(t, 10 + k)};
    const double before = corner_rms(d[0].corners, t.truth);
    refine_corners_linear(d, t.img, families, 2.2, EdgeRefineOptions{}, LinearCornerOptions{});
    const double after = corner_rms(d[0].corners, t.truth);
    EXPECT_GT(before, 0.3) << k;
    EXPECT_LT(after, 0.2) << k << " before " << before;  // (the photometric refinement takes it further)
    EXPECT_LT(after, 0.4 * before) << k << " before " << before;
    // The scan's own gamma is not applied on top (the neighbourhood is linear already).
    std::vector<Detection> e = {detection_on(t, 10 + k)};
    EdgeRefineOptions with_gamma;
    with_gamma.gamma = 2.2;
    refine_corners_linear(e, t.img, families, 2.2, with_gamma, LinearCornerOptions{});
    EXPECT_EQ(e[0].corners, d[0].corners) << k;
    // The homography and centre moved with the corners.
    const Eigen::Vector3d c = d[0].homography * Eigen::Vector3d(-1, -1, 1);
    EXPECT_LT((c.hnormalized() - d[0].corners[0]).norm(), 1e-9) << k;
    EXPECT_LT((d[0].center - d[0].homography.col(2).hnormalized()).norm(), 1e-9) << k;
  }
}

// Gamma 1 (linear input) or no valid gamma, a family not searched, or a move beyond the bound: the
// detection is left as it was.
TEST(LinearCorners, LeavesTheDetectionAloneWhenItHasNothingToDo) {
  const EncodedTag t = encoded_tag(3, 0.3);
  const Detection d0 = detection_on(t, 3);
  const std::vector<TagFamily> families = {builtin_family("36h11")};
  std::vector<Detection> d = {d0};
  for (const double gamma : {1.0, 0.0, -2.2, std::nan("")}) {  // linear input, or no gamma at all
    refine_corners_linear(d, t.img, families, gamma, EdgeRefineOptions{}, LinearCornerOptions{});
    EXPECT_EQ(d[0].corners, d0.corners) << gamma;
  }
  refine_corners_linear(d, t.img, std::vector<TagFamily>{builtin_family("25h9")}, 2.2, EdgeRefineOptions{},
                        LinearCornerOptions{});
  EXPECT_EQ(d[0].corners, d0.corners);
  LinearCornerOptions tight;
  tight.max_corner_shift_px = 0.01;  // the encoding's bias here is about 0.2 px
  refine_corners_linear(d, t.img, families, 2.2, EdgeRefineOptions{}, tight);
  EXPECT_EQ(d[0].corners, d0.corners);
}

// The whole detector on a gamma-encoded frame: input_gamma 2.2 finds the same tag as 1 does, with its
// corners nearer the truth; the paper profile does not depend on it at all.
TEST(LinearCorners, DetectorPlacesEncodedTagsSidesOnLinearIntensities) {
  const EncodedTag t = encoded_tag(42, 0.5);
  DetectorOptions lin, raw;
  lin.input_gamma = 2.2;
  const auto a = Detector(lin).detect(t.img), b = Detector(raw).detect(t.img);
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(a[0].id, 42);
  EXPECT_EQ(b[0].id, 42);
  EXPECT_LT(corner_rms(a[0].corners, t.truth), 0.06);
  EXPECT_LT(corner_rms(a[0].corners, t.truth), 0.5 * corner_rms(b[0].corners, t.truth));
  DetectorOptions p1 = DetectorOptions::paper(), p2 = DetectorOptions::paper();
  p1.input_gamma = 2.2;
  const auto c = Detector(p1).detect(t.img), e = Detector(p2).detect(t.img);
  ASSERT_EQ(c.size(), e.size());
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i].corners, e[i].corners);
}

}  // namespace test_linear_corners
