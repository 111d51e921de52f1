#include <gtest/gtest.h>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/payload_decode.hpp"
#include "synthetic_tag.hpp"

namespace test_payload_decode {

using namespace tagbench;

TEST(PayloadDecode, BilinearSamplingIsExactOnARamp) {
  ImageF img(10, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 10; ++x) img.at(x, y) = 0.05f * static_cast<float>(x) + 0.02f * static_cast<float>(y);
  EXPECT_NEAR(*sample_bilinear(img, Eigen::Vector2d(3.25, 4.5)), 0.05 * 3.25 + 0.02 * 4.5, 1e-6);
  EXPECT_NEAR(*sample_bilinear(img, Eigen::Vector2d(9, 7)), 0.05 * 9 + 0.02 * 7, 1e-6);
  EXPECT_FALSE(sample_bilinear(img, Eigen::Vector2d(-0.1, 2)).has_value());
  EXPECT_FALSE(sample_bilinear(img, Eigen::Vector2d(2, 7.01)).has_value());
}

TEST(PayloadDecode, ReadsTheCodeOfAWarpedTag) {
  for (const char* name : {"16h5", "25h9", "36h15"}) {
    const TagFamily& f = builtin_family(name);
    for (const int id : {0, 3}) {
      const Corners c = {Eigen::Vector2d(40.3, 35.8), Eigen::Vector2d(130.1, 45.2), Eigen::Vector2d(125.4, 128.9),
                         Eigen::Vector2d(35.6, 120.2)};
      const Eigen::Matrix3d H = synth::homography_for(c);
      const ImageF img = synth::render_tag(170, 165, tag_cells(f, id), H);
      const auto r = read_payload(img, H, f.payload_width(), {}, true);
      ASSERT_TRUE(r.has_value()) << name;
      EXPECT_EQ(r->bits, f.codes()[static_cast<std::size_t>(id)]) << name << " id " << id;
      EXPECT_GT(r->margin, 0.5);
      EXPECT_GT(r->contrast, 0.8);
      const int d = f.payload_width();
      EXPECT_EQ(r->payload_points.size(), static_cast<std::size_t>(d * d));
      EXPECT_EQ(r->white_points.size(), static_cast<std::size_t>(4 * (d + 3)));
      EXPECT_EQ(r->black_points.size(), static_cast<std::size_t>(4 * (d + 1)));
    }
  }
}

TEST(PayloadDecode, StartingFromAnotherCornerReadsARotation) {
  const TagFamily& f = builtin_family("25h9");
  const Corners c = synth::square_tag_corners(80, 80, 100, 0.2);
  const ImageF img = synth::render_tag(160, 160, tag_cells(f, 5), synth::homography_for(c));
  // The quad listed from the printed top-right corner: the reading is the code turned a quarter.
  const Corners shifted = {c[1], c[2], c[3], c[0]};
  const auto r = read_payload(img, synth::homography_for(shifted), 5);
  ASSERT_TRUE(r.has_value());
  const auto dec = f.decode(r->bits, 0);
  ASSERT_TRUE(dec.has_value());
  EXPECT_EQ(dec->id, 5);
  EXPECT_NE(dec->rotation, 0);
  EXPECT_EQ(r->bits, rotate(f.codes()[5], 5, dec->rotation));
}

TEST(PayloadDecode, StrongLightingGradientStillDecodes) {
  const TagFamily& f = builtin_family("36h15");
  const Corners c = synth::square_tag_corners(90, 90, 120, -0.3);
  const Eigen::Matrix3d H = synth::homography_for(c);
  ImageF img = synth::render_tag(180, 180, tag_cells(f, 7), H);
  // Light falls off by a factor of 8 across the tag: a single global threshold cannot read it.
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) *= static_cast<float>(1.0 - 0.875 * x / img.width);
  const auto r = read_payload(img, H, 6);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->bits, f.codes()[7]);
  // A global threshold (the mean of all payload samples' extremes) gets bits wrong here.
  float lo = 1, hi = 0;
  for (const float v : img.data) { lo = std::min(lo, v); hi = std::max(hi, v); }
  const float global = 0.5f * (lo + hi);
  Code naive = 0;
  const double cell = 2.0 / 8;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) {
      const Eigen::Vector2d p = apply_homography(H, Eigen::Vector2d(-1 + (x + 1.5) * cell, -1 + (y + 1.5) * cell));
      naive = (naive << 1) | (*sample_bilinear(img, p) > global ? 1u : 0u);
    }
  EXPECT_NE(naive, f.codes()[7]);
}

TEST(PayloadDecode, NoTagNoReading) {
  const ImageF flat(100, 100, 0.5f);
  const Corners c = synth::square_tag_corners(50, 50, 60, 0);
  EXPECT_FALSE(read_payload(flat, synth::homography_for(c), 6).has_value());
  // A quad partly outside the image cannot be read.
  const ImageF img(100, 100, 0.5f);
  const Corners out = synth::square_tag_corners(95, 50, 60, 0);
  EXPECT_FALSE(read_payload(img, synth::homography_for(out), 6).has_value());
}

}  // namespace test_payload_decode
