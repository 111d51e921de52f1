#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/decode_quads.hpp"
#include "detect/defocus_read.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"

namespace test_defocus_read {

using namespace tagbench;

namespace {

// A lens's defocus: every pixel the mean over a disk of radius r px (each kernel pixel weighted by
// the share of its area inside the disk, 8 x 8 sub-samples); edges clamped.
ImageF disk_blur(const ImageF& img, double r) {
  const int R = static_cast<int>(std::ceil(r));
  std::vector<double> k(static_cast<std::size_t>((2 * R + 1) * (2 * R + 1)), 0.0);
  for (int dy = -R; dy <= R; ++dy)
    for (int dx = -R; dx <= R; ++dx) {
      int in = 0;
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
          const double x = dx - 0.5 + (i + 0.5) / 8, y = dy - 0.5 + (j + 0.5) / 8;
          in += x * x + y * y <= r * r;
        }
      k[static_cast<std::size_t>((dy + R) * (2 * R + 1) + dx + R)] = in / 64.0;
    }
  const double sum = std::accumulate(k.begin(), k.end(), 0.0);
  ImageF out(img.width, img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double acc = 0;
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx)
          acc += k[static_cast<std::size_t>((dy + R) * (2 * R + 1) + dx + R)] *
                 img.at(std::clamp(x + dx, 0, img.width - 1), std::clamp(y + dy, 0, img.height - 1));
      out.at(x, y) = static_cast<float>(acc / sum);
    }
  return out;
}

// A small 36h11 tag (18 px black square, 2.25 px cells), turned, under a disk of 2.3 px radius
// (about a cell): the disk's first zero falls near the cell pitch.
Corners truth() { return synth::square_tag_corners(40.2, 39.7, 18, 0.3); }

ImageF defocused_tag(int id) {
  const ImageF sharp =
      synth::render_tag(80, 80, tag_cells(builtin_family("36h11"), id), synth::homography_for(truth()), 0.7f);
  return disk_blur(sharp, 2.3);
}

PayloadAreaOptions area() {  // the default profile's reader, as the detector passes it
  PayloadAreaOptions a;
  a.min_contrast = PayloadOptions{}.min_contrast;
  return a;
}

DefocusReadOptions on() { return DefocusReadOptions{}; }  // the default profile's

struct Attempt {
  std::vector<QuadOutcome> outcomes;     // the area reader's, then updated by the defocus reading
  std::vector<Detection> first, found;   // decode_quads' detections, the defocus reading's
};

Attempt attempt(const ImageF& img, const Quad& q, const DefocusReadOptions& opt,
                std::span<const Detection> decoded = {}) {
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  const PayloadAreaOptions a = area();
  Attempt t;
  t.first = decode_quads(img, std::vector<Quad>{q}, fams, 3, PayloadOptions{}, &a, nullptr, &t.outcomes, true);
  const DefocusModels models(fams, opt);
  t.found = read_defocused_quads(img, models, std::vector<Quad>{q}, t.outcomes, decoded, fams, 3, true, opt);
  return t;
}

// The quad a detector would hand over: the truth, each corner moved by up to 0.4 px (seeded).
Quad quad_near_truth(std::uint32_t seed) {
  Quad q;
  q.corners = synth::perturbed(truth(), 0.4, seed);
  return q;
}

}  // namespace

TEST(DefocusRead, DiskCellFractions) {
  const auto point = detail::disk_cell_fractions(3.4, 2.6, 0, 6);
  EXPECT_DOUBLE_EQ(point[2 * 6 + 3], 1.0);
  EXPECT_DOUBLE_EQ(std::accumulate(point.begin(), point.end(), 0.0), 1.0);
  // A disk of one cell's radius centred on a cell: the cell holds 1/pi of it (its square lies inside
  // the disk), each of the four edge neighbours as much as the others.
  const auto w = detail::disk_cell_fractions(2.5, 2.5, 1.0, 5);
  EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-12);
  EXPECT_NEAR(w[2 * 5 + 2], 1 / std::numbers::pi, 0.01);
  EXPECT_NEAR(w[1 * 5 + 2], w[3 * 5 + 2], 1e-12);
  EXPECT_NEAR(w[2 * 5 + 1], w[2 * 5 + 3], 1e-12);
  EXPECT_NEAR(w[1 * 5 + 2], w[2 * 5 + 1], 1e-12);
  EXPECT_EQ(w[0], 0.0);  // the corner cells' nearest point is 1.41 cells away
  // Past the grid's edge the weight stays on the edge cell.
  const auto edge = detail::disk_cell_fractions(0.2, 0.2, 1.0, 3);
  EXPECT_NEAR(std::accumulate(edge.begin(), edge.end(), 0.0), 1.0, 1e-12);
  EXPECT_GT(edge[0], 0.5);
}

// Under a disk about a cell wide the area reader misreads most small tags even from quads within
// 0.4 px of the truth; the defocus reading decodes most of those, every one as its own id, with
// corners near the truth and the quad's outcome updated.
TEST(DefocusRead, ReadsSmallTagsTheAreaReaderMisreadsUnderADisk) {
  int misread = 0, rescued = 0;
  for (int id = 0; id < 24; ++id) {
    const ImageF img = defocused_tag(id);
    const Attempt t = attempt(img, quad_near_truth(static_cast<std::uint32_t>(100 + id)), on());
    if (!t.first.empty()) {
      EXPECT_EQ(t.first[0].id, id);
      EXPECT_TRUE(t.found.empty());  // a decoded quad is no candidate
      continue;
    }
    ++misread;
    if (t.found.empty()) continue;
    ++rescued;
    ASSERT_EQ(t.found.size(), 1u);
    EXPECT_EQ(t.found[0].family, "36h11");
    EXPECT_EQ(t.found[0].id, id);
    EXPECT_LE(t.found[0].hamming, 2);  // corrected bits (3) less spare_bits (1)
    EXPECT_LT(synth::corner_rms(t.found[0].corners, truth()), 0.6);
    EXPECT_NEAR((t.found[0].center - apply_homography(t.found[0].homography, Eigen::Vector2d::Zero())).norm(), 0,
                1e-9);
    EXPECT_EQ(t.outcomes[0].fate, QuadOutcome::Fate::kDecoded);
    EXPECT_EQ(t.outcomes[0].id, id);
  }
  EXPECT_GE(misread, 16);  // 21 of the 24 when written
  EXPECT_GE(rescued, misread - 3);  // all 21 when written
}

// Off, a family too close (min_family_hamming above 36h11's 11), no code explaining the samples
// (max_hypothesis_cost 0), quads outside the side range or centred inside a tag found already, a
// quad already decoded: nothing.
TEST(DefocusRead, GatesKeepItFromTrying) {
  // The first id the area reader misreads and the defocus reading decodes.
  int id = -1;
  for (int i = 0; i < 24 && id < 0; ++i) {
    const Attempt t = attempt(defocused_tag(i), quad_near_truth(static_cast<std::uint32_t>(100 + i)), on());
    if (t.first.empty() && t.found.size() == 1) id = i;
  }
  ASSERT_GE(id, 0);
  const ImageF img = defocused_tag(id);
  const Quad q = quad_near_truth(static_cast<std::uint32_t>(100 + id));
  ASSERT_EQ(attempt(img, q, on()).found.size(), 1u);
  DefocusReadOptions off;
  off.enabled = false;
  EXPECT_TRUE(attempt(img, q, off).found.empty());
  DefocusReadOptions far_families = on();
  far_families.min_family_hamming = 12;
  EXPECT_TRUE(attempt(img, q, far_families).found.empty());
  DefocusReadOptions no_fit = on();
  no_fit.max_hypothesis_cost = 0;
  EXPECT_TRUE(attempt(img, q, no_fit).found.empty());
  DefocusReadOptions large_only = on();
  large_only.min_side_px = 25;
  EXPECT_TRUE(attempt(img, q, large_only).found.empty());
  DefocusReadOptions small_only = on();
  small_only.max_side_px = 12;
  EXPECT_TRUE(attempt(img, q, small_only).found.empty());
  Detection there;
  there.corners = synth::square_tag_corners(40, 40, 24, 0);
  EXPECT_TRUE(attempt(img, q, on(), std::vector<Detection>{there}).found.empty());
  Detection elsewhere;
  elsewhere.corners = synth::square_tag_corners(200, 200, 24, 0);
  EXPECT_EQ(attempt(img, q, on(), std::vector<Detection>{elsewhere}).found.size(), 1u);
  // Outcomes and quads not parallel: nothing.
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  const DefocusModels models(fams, on());
  std::vector<QuadOutcome> none;
  EXPECT_TRUE(read_defocused_quads(img, models, std::vector<Quad>{q}, none, {}, fams, 3, true, on()).empty());
}

// Quads on texture blurred by the same disk: some readings lie within 7 bits of a 36h11 code and the
// model explains a few of them, but no placement makes texture read as a code: no detection from
// 1000 quads on a random checkerwork of 2-3 px blocks.
TEST(DefocusRead, TextureGivesNoDetection) {
  std::mt19937 rng(7);
  std::bernoulli_distribution dark(0.5);
  std::uniform_int_distribution<int> block(2, 3);
  ImageF blocks(201, 201);
  for (int y0 = 0; y0 < 201;) {
    const int h = block(rng);
    for (int x0 = 0; x0 < 201;) {
      const int w = block(rng);
      const float v = dark(rng) ? 0.1f : 0.9f;
      for (int y = y0; y < std::min(201, y0 + h); ++y)
        for (int x = x0; x < std::min(201, x0 + w); ++x) blocks.at(x, y) = v;
      x0 += w;
    }
    y0 += h;
  }
  const ImageF img = disk_blur(blocks, 2.0);
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  std::uniform_real_distribution<double> pos(40, 160), side(12, 30), turn(0, 1.5);
  std::vector<Quad> quads;
  for (int i = 0; i < 1000; ++i) {
    Quad q;
    q.corners = synth::perturbed(synth::square_tag_corners(pos(rng), pos(rng), side(rng), turn(rng)), 1, 300 + i);
    quads.push_back(q);
  }
  const PayloadAreaOptions a = area();
  std::vector<QuadOutcome> outcomes;
  const auto first = decode_quads(img, quads, fams, 3, PayloadOptions{}, &a, nullptr, &outcomes, true);
  EXPECT_TRUE(first.empty());
  int near_a_code = 0;  // readings within the hypothesis' 7 bits: the test exercises the placement
  for (const auto& o : outcomes)
    if (o.fate == QuadOutcome::Fate::kNotDecoded && fams[0].decode(*o.bits[6], 7)) ++near_a_code;
  EXPECT_GT(near_a_code, 20);
  const DefocusModels models(fams, on());
  EXPECT_TRUE(read_defocused_quads(img, models, quads, outcomes, first, fams, 3, true, on()).empty());
  // Not even with every hypothesis placed (no model-fit gate) and the family's whole correction.
  DefocusReadOptions every = on();
  every.max_hypothesis_cost = 1e9;
  every.spare_bits = 0;
  std::vector<QuadOutcome> again;
  decode_quads(img, quads, fams, 3, PayloadOptions{}, &a, nullptr, &again, true);
  EXPECT_TRUE(read_defocused_quads(img, models, quads, again, first, fams, 3, true, every).empty());
}

// The profiles: on in the default and the thorough, off in the paper's; the options validated by name.
TEST(DefocusRead, ProfilesAndValidation) {
  EXPECT_TRUE(DetectorOptions{}.defocus_read.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().defocus_read.enabled);
  EXPECT_FALSE(DetectorOptions::paper().defocus_read.enabled);
  DetectorOptions o;
  o.defocus_read.radii_cells = {0, 0.8, 0.7};
  try {
    Detector d{o};
    ADD_FAILURE() << "descending radii accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("defocus_read.radii_cells"), std::string::npos) << e.what();
  }
  o = DetectorOptions{};
  o.defocus_read.radii_cells = {-0.1};
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o = DetectorOptions{};
  o.defocus_read.samples_per_cell = 0;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o = DetectorOptions{};
  o.defocus_read.max_side_px = 1;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o = DetectorOptions{};
  o.defocus_read.final_step_px = 0;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o = DetectorOptions{};
  o.defocus_read.initial_step_px = 0.01;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
}

}  // namespace test_defocus_read
