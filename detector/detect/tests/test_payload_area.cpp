#include <gtest/gtest.h>

#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/payload_area.hpp"
#include "synthetic_tag.hpp"

namespace test_payload_area {

using namespace tagbench;

// One sample per cell and no sharpening is the paper's reading, bit for bit and margin for margin.
TEST(PayloadArea, OneSampleNoSharpeningIsThePapersReading) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = {Eigen::Vector2d(20.3, 15.8), Eigen::Vector2d(60.1, 19.2), Eigen::Vector2d(57.4, 58.9),
                     Eigen::Vector2d(17.6, 55.2)};
  const Eigen::Matrix3d H = synth::homography_for(c);
  ImageF img = gaussian_blur(synth::render_tag(80, 80, tag_cells(f, 9), H), 1.2);
  PayloadOptions paper;
  paper.quick_reject = false;
  PayloadAreaOptions one;
  one.samples_per_side = 1;
  one.sharpening = 0;
  const auto a = read_payload(img, H, 6, paper), b = read_payload_area(img, H, 6, one);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->bits, b->bits);
  EXPECT_NEAR(a->margin, b->margin, 1e-6);
  EXPECT_NEAR(a->contrast, b->contrast, 1e-6);
}

// A 14 px tag (1.75 px cells) blurred at sigma 0.8 px with noise: over 20 ids the area reading with
// sharpening gets every code right, and more than the paper's single sample does.
TEST(PayloadArea, SmallBlurredNoisyTagsReadBetterThanOneSample) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.03f);
  int paper_right = 0, area_right = 0;
  for (int id = 0; id < 20; ++id) {
    const Corners c = synth::square_tag_corners(20.2 + 0.13 * id, 19.7, 14.0, 0.15 * id);
    const Eigen::Matrix3d H = synth::homography_for(c);
    ImageF img = gaussian_blur(synth::render_tag(40, 40, tag_cells(f, id), H), 0.8);
    for (auto& v : img.data) v += noise(rng);
    PayloadOptions paper;
    paper.quick_reject = false;
    const auto a = read_payload(img, H, 6, paper);
    const auto b = read_payload_area(img, H, 6);
    ASSERT_TRUE(b.has_value());
    const Code truth = f.codes()[static_cast<std::size_t>(id)];
    paper_right += a && a->bits == truth;
    area_right += b->bits == truth;
  }
  EXPECT_EQ(area_right, 20);
  EXPECT_LT(paper_right, area_right);
}

TEST(PayloadArea, NoContrastOrOffImageGivesNothing) {
  const Corners c = synth::square_tag_corners(20, 20, 16, 0);
  const Eigen::Matrix3d H = synth::homography_for(c);
  EXPECT_FALSE(read_payload_area(ImageF(40, 40, 0.5f), H, 6).has_value());
  const TagFamily& f = builtin_family("36h11");
  const ImageF img = synth::render_tag(40, 40, tag_cells(f, 2), H);
  const Corners off = synth::square_tag_corners(2, 20, 16, 0);  // payload partly left of the image
  EXPECT_FALSE(read_payload_area(img, synth::homography_for(off), 6).has_value());
  PayloadAreaOptions bad;
  bad.samples_per_side = 0;
  EXPECT_FALSE(read_payload_area(img, H, 6, bad).has_value());
}

// Cells under small_cell_px are read with small_cell_sharpening, larger ones with sharpening: the
// reading of a 9 px tag (1.125 px cells) is the one at sharpening 0.75, a 14 px tag's the one at 0.5.
TEST(PayloadArea, SmallCellsGetTheirOwnSharpening) {
  const TagFamily& f = builtin_family("36h11");
  const auto read = [&](double side, double sharpening, double small_px) {
    const Corners c = synth::square_tag_corners(20.3, 19.6, side, 0.7);
    const Eigen::Matrix3d H = synth::homography_for(c);
    const ImageF img = gaussian_blur(synth::render_tag(40, 40, tag_cells(f, 17), H), 0.9);
    PayloadAreaOptions o;
    o.sharpening = sharpening;
    o.small_cell_px = small_px;
    const auto r = read_payload_area(img, H, 6, o);
    EXPECT_TRUE(r.has_value());
    return r ? r->margin : -1.0;
  };
  // 9 px: small; the default reading is the 0.75 reading, not the 0.5 one.
  EXPECT_DOUBLE_EQ(read(9, 0.5, 1.2), read(9, 0.75, 0));
  EXPECT_NE(read(9, 0.5, 1.2), read(9, 0.5, 0));
  // 14 px (1.75 px cells): untouched.
  EXPECT_DOUBLE_EQ(read(14, 0.5, 1.2), read(14, 0.5, 0));
}

}  // namespace test_payload_area
