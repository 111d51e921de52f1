#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/code_refit.hpp"
#include "detect/decode_quads.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"

namespace test_code_refit {

using namespace tagbench;

namespace {

constexpr int kId = 17;

// A small 36h11 tag (22 px black square, 2.75 px cells), turned and blurred as a small tag in a photo.
Corners truth() { return synth::square_tag_corners(40.3, 39.6, 22, 0.35); }

ImageF tag_image() {
  return gaussian_blur(synth::render_tag(80, 80, tag_cells(builtin_family("36h11"), kId), synth::homography_for(truth())),
                       0.9);
}

// The default profile's reader, as the detector passes it.
PayloadAreaOptions area() {
  PayloadAreaOptions a;
  a.min_contrast = PayloadOptions{}.min_contrast;
  return a;
}

// A quad off the tag by 1-2.5 px a corner whose reading misses the code by 4-7 bits (more than the 3
// corrected, within the hypothesis' 7), and its outcome; found by trying seeded perturbations.
struct Misplaced {
  Quad quad;
  QuadOutcome outcome;
  int bits_wrong = -1;
};

std::optional<Misplaced> misplaced_quad() {
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  const ImageF img = tag_image();
  const PayloadAreaOptions a = area();
  for (std::uint32_t seed = 1; seed < 400; ++seed) {
    Quad q;
    q.corners = synth::perturbed(truth(), 2.5, seed);
    std::vector<QuadOutcome> outcomes;
    if (!decode_quads(img, std::vector<Quad>{q}, fams, 3, PayloadOptions{}, &a, nullptr, &outcomes, true).empty())
      continue;
    if (outcomes[0].fate != QuadOutcome::Fate::kNotDecoded) continue;
    const auto near = f.decode(*outcomes[0].bits[6], 7);
    if (!near || near->id != kId) continue;
    return Misplaced{q, outcomes[0], near->hamming};
  }
  return std::nullopt;
}

std::vector<Detection> refit(const Misplaced& m, std::span<const Detection> decoded, const CodeRefitOptions& opt,
                             QuadOutcome* outcome_out = nullptr) {
  const std::vector<TagFamily> fams{builtin_family("36h11")};
  const ImageF img = tag_image();
  std::vector<QuadOutcome> outcomes{m.outcome};
  auto found = refit_to_nearest_codes(img, img, std::vector<Quad>{m.quad}, outcomes, decoded, fams, 3, true, area(), opt);
  if (outcome_out) *outcome_out = outcomes[0];
  return found;
}

}  // namespace

// A quad a couple of pixels off a small tag reads 4-7 bits wrong; placed by its nearest code's pattern
// and read again, it decodes to the tag, with corners near the truth and its outcome updated.
TEST(CodeRefit, MisplacedQuadOfASmallTagIsPlacedAndDecoded) {
  const auto m = misplaced_quad();
  ASSERT_TRUE(m.has_value()) << "no seeded perturbation gave a 4-7 bit misreading";
  EXPECT_GE(m->bits_wrong, 4);
  QuadOutcome outcome;
  const auto found = refit(*m, {}, CodeRefitOptions{}, &outcome);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].family, "36h11");
  EXPECT_EQ(found[0].id, kId);
  EXPECT_LE(found[0].hamming, 2);  // corrected bits (3) less spare_bits (1)
  // The refined corners are in printed order; the truth's square is printed upright.
  EXPECT_LT(synth::corner_rms(found[0].corners, truth()), 0.5);
  EXPECT_GT(synth::corner_rms(m->quad.corners, truth()), 1.0);
  EXPECT_NEAR((found[0].center - apply_homography(found[0].homography, Eigen::Vector2d::Zero())).norm(), 0, 1e-9);
  EXPECT_EQ(outcome.fate, QuadOutcome::Fate::kDecoded);
  EXPECT_EQ(outcome.id, kId);
}

// Off, a family too close for the hypothesis (min_family_hamming above 36h11's 11), a hypothesis
// bound below the misreading, no disagreement weak enough, a quad outside the side range or inside a
// tag already found: nothing.
TEST(CodeRefit, GatesKeepItFromTrying) {
  const auto m = misplaced_quad();
  ASSERT_TRUE(m.has_value());
  ASSERT_EQ(refit(*m, {}, CodeRefitOptions{}).size(), 1u);
  CodeRefitOptions off;
  off.enabled = false;
  EXPECT_TRUE(refit(*m, {}, off).empty());
  CodeRefitOptions far_families;
  far_families.min_family_hamming = 12;
  EXPECT_TRUE(refit(*m, {}, far_families).empty());
  CodeRefitOptions tight;
  tight.max_bits = m->bits_wrong - 1;
  EXPECT_TRUE(refit(*m, {}, tight).empty());
  CodeRefitOptions firm_only;  // every disagreeing cell counts as firm: no hypothesis is weak enough
  firm_only.max_weak_distance = 0;
  EXPECT_TRUE(refit(*m, {}, firm_only).empty());
  CodeRefitOptions large_only;
  large_only.min_side_px = 30;
  EXPECT_TRUE(refit(*m, {}, large_only).empty());
  CodeRefitOptions small_only;
  small_only.max_side_px = 15;
  EXPECT_TRUE(refit(*m, {}, small_only).empty());
  Detection there;
  there.corners = synth::square_tag_corners(40, 40, 30, 0);
  EXPECT_TRUE(refit(*m, std::vector<Detection>{there}, CodeRefitOptions{}).empty());
  Detection elsewhere;
  elsewhere.corners = synth::square_tag_corners(200, 200, 30, 0);
  EXPECT_EQ(refit(*m, std::vector<Detection>{elsewhere}, CodeRefitOptions{}).size(), 1u);
  // A quad decoded already, or not read, is not a candidate.
  Misplaced decoded = *m;
  decoded.outcome.fate = QuadOutcome::Fate::kDecoded;
  EXPECT_TRUE(refit(decoded, {}, CodeRefitOptions{}).empty());
}

// Quads on texture: many readings lie within 7 bits of some 36h11 code, but a placement fitted to
// that code cannot make the texture read as it: no detection from 1000 quads on a blurred random
// checkerwork of 3 px blocks (cell-sized dark and light patches, as a tag's payload has).
TEST(CodeRefit, TextureGivesNoDetection) {
  std::mt19937 rng(5);
  std::bernoulli_distribution dark(0.5);
  ImageF blocks(201, 201);
  for (int by = 0; by < 67; ++by)
    for (int bx = 0; bx < 67; ++bx) {
      const float v = dark(rng) ? 0.1f : 0.9f;
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) blocks.at(3 * bx + x, 3 * by + y) = v;
    }
  const ImageF img = gaussian_blur(blocks, 0.9);
  const TagFamily& f = builtin_family("36h11");
  const std::vector<TagFamily> fams{f};
  std::uniform_real_distribution<double> pos(40, 160), side(14, 40), turn(0, 1.5);
  std::vector<Quad> quads;
  for (int i = 0; i < 1000; ++i) {
    Quad q;
    q.corners = synth::perturbed(synth::square_tag_corners(pos(rng), pos(rng), side(rng), turn(rng)), 2, 100 + i);
    quads.push_back(q);
  }
  const PayloadAreaOptions a = area();
  std::vector<QuadOutcome> outcomes;
  const auto first = decode_quads(img, quads, fams, 3, PayloadOptions{}, &a, nullptr, &outcomes, true);
  int hypotheses = 0;
  for (const auto& o : outcomes)
    if (o.fate == QuadOutcome::Fate::kNotDecoded && f.decode(*o.bits[6], 7)) ++hypotheses;
  EXPECT_GT(hypotheses, 20);  // the test exercises the placement, not only the gate
  EXPECT_TRUE(refit_to_nearest_codes(img, img, quads, outcomes, first, fams, 3, true, a, CodeRefitOptions{}).empty());
  // Not even when every hypothesis is placed (no weak-disagreement test): the re-read refuses them.
  CodeRefitOptions every;
  every.max_weak_distance = 1e9;
  EXPECT_TRUE(refit_to_nearest_codes(img, img, quads, outcomes, first, fams, 3, true, a, every).empty());
}

// The profiles: on in the default, off in the paper's; its options are validated by name.
TEST(CodeRefit, ProfilesAndValidation) {
  EXPECT_TRUE(DetectorOptions{}.code_refit.enabled);
  EXPECT_FALSE(DetectorOptions::paper().code_refit.enabled);
  DetectorOptions o;
  o.code_refit.max_bits = -1;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o = DetectorOptions{};
  o.code_refit.refine.iterations = 0;
  try {
    Detector d{o};
    ADD_FAILURE() << "iterations 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("code_refit.refine.iterations"), std::string::npos) << e.what();
  }
  o = DetectorOptions{};
  o.code_refit.max_side_px = 1;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
}

}  // namespace test_code_refit
