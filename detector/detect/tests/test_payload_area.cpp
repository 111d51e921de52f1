#include <gtest/gtest.h>

#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/decode_quads.hpp"
#include "detect/homography.hpp"
#include "detect/payload_area.hpp"
#include "synthetic.hpp"
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

// A homography whose whole sample grid lands inside the image is read without a bounds test per
// sample; the reading is the same as through a map the reader must test sample by sample (and as
// before where the grid leaves the image): tags well inside, at the edge, past it, and steeply tilted.
TEST(PayloadArea, TheGridTestedOnceReadsAsEverySampleTested) {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<Corners> places = {
      synth::square_tag_corners(30, 30, 16, 0.3), synth::square_tag_corners(11, 30, 16, 0),
      synth::square_tag_corners(10.2, 30, 16, 0), synth::square_tag_corners(8, 30, 16, 0.1),
      Corners{Eigen::Vector2d(12, 8), Eigen::Vector2d(50, 14), Eigen::Vector2d(47, 30), Eigen::Vector2d(15, 27)}};
  int read = 0;
  for (const Corners& c : places) {
    const Eigen::Matrix3d H = synth::homography_for(c);
    ImageF img = synth::render_tag(60, 60, tag_cells(f, 5), H);
    synth::add_gaussian_noise(img, 0.02, 3);
    const auto a = read_payload_area(img, H, 6);
    const auto b = read_payload_area(img, TagToImage([&](const Eigen::Vector2d& u) { return apply_homography(H, u); }), 6);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) continue;
    ++read;
    EXPECT_EQ(a->bits, b->bits);
    EXPECT_EQ(a->margin, b->margin);
    EXPECT_EQ(a->contrast, b->contrast);
    EXPECT_EQ(a->confidence, b->confidence);
  }
  EXPECT_GE(read, 3);
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

// A tag whose white ring is as dark as its black ring (a 1-cell ring blurred into a dark card): the
// rings' models see no contrast, so the area reading gives nothing; the payload's own two levels still
// read the code (read_payload_self_threshold), and decode_quads finds the tag only with the option on.
TEST(PayloadSelfThreshold, ReadsATagWhoseWhiteRingIsLost) {
  const TagFamily& f = builtin_family("36h11");
  TagCells cells = tag_cells(f, 42);
  for (int y = 0; y < cells.n; ++y)
    for (int x = 0; x < cells.n; ++x)
      if (std::min({x, y, cells.n - 1 - x, cells.n - 1 - y}) == 0) cells.white[static_cast<std::size_t>(y * cells.n + x)] = 0;
  const Corners c = synth::square_tag_corners(30.2, 29.7, 22, 0.3);
  const Eigen::Matrix3d H = synth::homography_for(c);
  const ImageF img = gaussian_blur(synth::render_tag(60, 60, cells, H, 0.05f), 0.8);
  EXPECT_FALSE(read_payload_area(img, H, 6).has_value());
  const auto r = read_payload_self_threshold(img, H, 6, PayloadAreaOptions{});
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->bits, f.codes()[42]);
  EXPECT_GT(r->contrast, 0.5);
  EXPECT_GT(r->margin, 0.0);

  const std::vector<TagFamily> fams = {f};
  Quad q;
  q.corners = c;
  PayloadOptions payload;
  payload.quick_reject = false;  // the pre-filter asks for a white ring: there is none here
  PayloadAreaOptions area;
  EXPECT_TRUE(decode_quads(img, std::vector<Quad>{q}, fams, 3, payload, &area).empty());
  area.self_threshold.enabled = true;
  const auto found = decode_quads(img, std::vector<Quad>{q}, fams, 3, payload, &area);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 42);
  EXPECT_EQ(found[0].hamming, 0);
  // spare_bits and min_family_hamming limit it: 36h11's 11 is under 12.
  area.self_threshold.min_family_hamming = 12;
  EXPECT_TRUE(decode_quads(img, std::vector<Quad>{q}, fams, 3, payload, &area).empty());
}

// Texture is not a tag: on noise, a quad's black ring is as often above the payload's split as
// below it, so few noise quads give a reading at all (and none of those decodes as 36h11 within 3
// bits); a flat quad has one level only.
TEST(PayloadSelfThreshold, RefusesMostNoiseAndFlatQuads) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Eigen::Matrix3d H = synth::homography_for(synth::square_tag_corners(30, 30, 22, 0.2));
  int read = 0, decoded = 0;
  for (int k = 0; k < 100; ++k) {
    ImageF img(60, 60, 0.0f);
    for (auto& v : img.data) v = u(rng);
    const auto r = read_payload_self_threshold(gaussian_blur(img, 0.8), H, 6, PayloadAreaOptions{});
    read += r.has_value();
    decoded += r && f.decode(r->bits, 3).has_value();
  }
  EXPECT_LE(read, 10);
  EXPECT_EQ(decoded, 0);
  EXPECT_FALSE(read_payload_self_threshold(ImageF(60, 60, 0.5f), H, 6, PayloadAreaOptions{}).has_value());
}

// The homography reader's samples (taken two at a time) sum to the same cell means as the generic
// map's, for k = 1..5 samples a side and random perspective quads over a random image.
TEST(PayloadArea, HomographyReadingEqualsTheGenericMapsOnRandomQuads) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  ImageF img;
  img.width = 80, img.height = 70;
  img.data.resize(static_cast<std::size_t>(img.width * img.height));
  for (float& v : img.data) v = static_cast<float>(u01(rng));
  int read = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double cx = 25 + 30 * u01(rng), cy = 25 + 20 * u01(rng), r = 6 + 12 * u01(rng), a = 6.3 * u01(rng);
    Corners c;
    for (int i = 0; i < 4; ++i) {
      const double t = a + i * M_PI / 2;
      c[static_cast<std::size_t>(i)] = Eigen::Vector2d(cx + r * std::cos(t) + 3 * u01(rng), cy + r * std::sin(t) + 3 * u01(rng));
    }
    const Eigen::Matrix3d H = synth::homography_for(c);
    PayloadAreaOptions opt;
    opt.samples_per_side = 1 + trial % 5;
    opt.min_contrast = 0;
    const auto x = read_payload_area(img, H, 6, opt);
    const auto y = read_payload_area(img, TagToImage([&](const Eigen::Vector2d& p) { return apply_homography(H, p); }), 6, opt);
    ASSERT_EQ(x.has_value(), y.has_value()) << trial;
    if (!x) continue;
    ++read;
    EXPECT_EQ(x->bits, y->bits) << trial;
    EXPECT_EQ(x->margin, y->margin) << trial;
    EXPECT_EQ(x->contrast, y->contrast) << trial;
    EXPECT_EQ(x->confidence, y->confidence) << trial;
  }
  EXPECT_GE(read, 20);
}

}  // namespace test_payload_area
