#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/decode_quads.hpp"
#include "detect/payload_area.hpp"
#include "detect/soft_decode.hpp"
#include "synthetic_tag.hpp"

namespace test_soft_decode {

using namespace tagbench;

namespace {

// Confidences of a code: +-amp per cell (MSB first), plus Gaussian noise.
std::vector<float> confidences_of(Code w, int n, double amp, double noise, std::mt19937& rng) {
  std::normal_distribution<double> g(0, noise);
  std::vector<float> z(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) z[static_cast<std::size_t>(k)] = static_cast<float>(((w >> (n - 1 - k)) & 1u ? amp : -amp) + g(rng));
  return z;
}

// Brute force: every word's weighted distance (soft_decode.hpp: |z| over its mean, capped).
std::vector<double> distances(const TagFamily& f, const std::vector<float>& z, double cap) {
  const int n = f.bits();
  double scale = 0;
  for (const float v : z) scale += std::abs(v) / n;
  std::vector<double> d;
  for (const Code w : f.rotated_words()) {
    double s = 0;
    for (int k = 0; k < n; ++k) {
      const bool bit = (w >> (n - 1 - k)) & 1u;
      if (bit != (z[static_cast<std::size_t>(k)] > 0)) s += std::min<double>(std::abs(z[static_cast<std::size_t>(k)]) / scale, cap);
    }
    d.push_back(s);
  }
  return d;
}

PayloadReading reading_of(std::vector<float> z) {
  PayloadReading r;
  r.confidence = std::move(z);
  return r;
}

}  // namespace

// The pruned search finds exactly the brute force's best and second-best distances.
TEST(SoftDecode, MatchIsTheBruteForceBestAndSecond) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> id(0, static_cast<int>(f.size()) - 1);
  for (int t = 0; t < 200; ++t) {
    const auto z = t % 2 ? confidences_of(f.codes()[static_cast<std::size_t>(id(rng))], 36, 0.8, 0.7, rng)
                         : confidences_of(rng() & low_mask(36), 36, 0.5, 1.0, rng);
    const SoftMatch m = soft_match(f, z);
    auto d = distances(f, z, SoftDecodeOptions{}.confidence_cap);
    ASSERT_GE(m.best, 0);
    EXPECT_NEAR(m.best_distance, d[static_cast<std::size_t>(m.best)], 1e-6);
    std::sort(d.begin(), d.end());
    EXPECT_NEAR(m.best_distance, d[0], 1e-6);
    EXPECT_NEAR(m.second_distance, d[1], 1e-6);
    EXPECT_EQ(m.best_bit_errors,
              std::popcount(f.rotated_words()[static_cast<std::size_t>(m.best)] ^
                            [&] { Code h = 0; for (int k = 0; k < 36; ++k) if (z[static_cast<std::size_t>(k)] > 0) h |= Code{1} << (35 - k); return h; }()));
  }
}

// Random patterns (not codes) are refused: over 100000 of them, of every amplitude and noise, the
// soft rule accepts fewer than the hard decoder (3 bits corrected) accepts of their hard bits (about
// 2348 x 7807 / 2^36 = 2.7e-4 of random words for 36h11, 1.1e-3 for 36h10), a quarter of that at most.
TEST(SoftDecode, RandomPatternsAreRefused) {
  for (const char* name : {"36h11", "36h10"}) {
    const TagFamily& f = builtin_family(name);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> amp(0.2, 2.0), noise(0.05, 1.0);
    int soft = 0, hard = 0;
    for (int t = 0; t < 100000; ++t) {
      const auto z = confidences_of((Code(rng()) | Code(rng()) << 32) & low_mask(36), 36, amp(rng), noise(rng), rng);
      Code bits = 0;
      for (const float v : z) bits = (bits << 1) | (v > 0 ? 1u : 0u);
      hard += f.decode(bits, 3).has_value();
      soft += soft_decode(f, reading_of(z)).has_value();
    }
    EXPECT_LE(soft, hard / 4) << name;
    std::printf("%s random patterns accepted: soft %d, hard (3 bits) %d of 100000\n", name, soft, hard);
  }
}

// Noisy readings of a code are decoded as that code or refused, never as another code; and between
// two codes (half the bits where they differ leaning each way, weakly) the rule refuses.
TEST(SoftDecode, NeverAWrongCode) {
  for (const char* name : {"36h11", "36h10"}) {
    const TagFamily& f = builtin_family(name);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> pick(0, static_cast<int>(f.size()) - 1);
    std::uniform_real_distribution<double> noise(0.3, 1.2);
    int right = 0, wrong = 0;
    for (int t = 0; t < 20000; ++t) {
      const int id = pick(rng), rot = static_cast<int>(rng() % 4);
      const Code w = rotate(f.codes()[static_cast<std::size_t>(id)], 6, rot);
      const auto dec = soft_decode(f, reading_of(confidences_of(w, 36, 1.0, noise(rng), rng)));
      if (!dec) continue;
      (dec->id == id && dec->rotation == rot ? right : wrong)++;
    }
    EXPECT_EQ(wrong, 0) << name;
    EXPECT_GT(right, 100) << name;  // and it does accept readings the hard decoder (3 bits) need not
    // Between code a and its nearest word b: the differing bits split, weak both ways.
    int between = 0;
    for (int t = 0; t < 200; ++t) {
      const Code a = f.codes()[static_cast<std::size_t>(pick(rng))];
      Code b = 0;
      int best = 64;
      for (const Code w : f.rotated_words())
        if (w != a && std::popcount(w ^ a) < best) best = std::popcount(w ^ a), b = w;
      auto z = confidences_of(a, 36, 1.0, 0.0, rng);
      int flip = 0;
      for (int k = 0; k < 36; ++k)
        if (((a ^ b) >> (35 - k)) & 1u) z[static_cast<std::size_t>(k)] = (flip++ % 2 ? 0.15f : -0.15f) * (z[static_cast<std::size_t>(k)] > 0 ? 1 : -1);
      between += soft_decode(f, reading_of(z)).has_value();
    }
    EXPECT_EQ(between, 0) << name;
  }
}

// Small families (16h5, 25h9) are never soft decoded by default (min_family_hamming 10); 36h10 is.
TEST(SoftDecode, SmallFamiliesAreLeftAlone) {
  std::mt19937 rng(1);
  const TagFamily& f25 = builtin_family("25h9");
  EXPECT_FALSE(soft_decode(f25, reading_of(confidences_of(f25.codes()[3], 25, 1.0, 0.0, rng))).has_value());
  const TagFamily& f10 = builtin_family("36h10");
  EXPECT_TRUE(soft_decode(f10, reading_of(confidences_of(f10.codes()[3], 36, 1.0, 0.0, rng))).has_value());
  const TagFamily& f = builtin_family("16h5");
  const auto z = confidences_of(f.codes()[3], 16, 1.0, 0.0, rng);
  EXPECT_FALSE(soft_decode(f, reading_of(z)).has_value());
  SoftDecodeOptions o;
  o.min_family_hamming = 5;
  EXPECT_TRUE(soft_decode(f, reading_of(z), o).has_value());
}

// A low-contrast, noisy, blurred 20 px tag: the area reader's hard bits are often beyond the 3 bits
// 36h11 corrects; the soft decoder reads more of them, and never a wrong id.
TEST(SoftDecode, ReadsLowContrastNoisyTagsTheHardDecoderMisses) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(17);
  std::normal_distribution<float> noise(0.0f, 0.045f);
  int hard = 0, soft = 0, wrong = 0;
  for (int id = 0; id < 60; ++id) {
    const Corners c = synth::square_tag_corners(25.2 + 0.11 * id, 24.7, 20.0, 0.13 * id);
    const Eigen::Matrix3d H = synth::homography_for(c);
    ImageF img = gaussian_blur(synth::render_tag(50, 50, tag_cells(f, id), H, 0.5f, 8, 0.42f, 0.58f), 1.1);
    for (auto& v : img.data) v += noise(rng);
    const auto r = read_payload_area(img, H, 6);
    ASSERT_TRUE(r.has_value());
    if (const auto dec = f.decode(r->bits, 3)) {
      hard += dec->id == id;
      continue;
    }
    if (const auto dec = soft_decode(f, *r)) (dec->id == id && dec->rotation == 0 ? soft : wrong)++;
  }
  std::printf("low-contrast 20 px tags: hard %d, soft %d more, wrong %d of 60\n", hard, soft, wrong);
  EXPECT_EQ(wrong, 0);
  EXPECT_GE(soft, 3);
  EXPECT_LT(hard, 60);
}

namespace {
// Faint, blurred, noisy renders of 36h11 tags (ids from 0, below max_id) through corners_of(id) on a
// 50 x 50 image; for each of the first `want` that only the soft decoder reads (the hard decoder
// refuses it within 3 bits), check(image, the quad of those corners, id). Returns how many were checked.
template <class CornersOf, class Check>
int for_soft_only_tags(unsigned seed, int max_id, int want, CornersOf corners_of, Check check) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.045f);
  int checked = 0;
  for (int id = 0; id < max_id && checked < want; ++id) {
    Quad q;
    q.corners = corners_of(id);
    const Eigen::Matrix3d H = synth::homography_for(q.corners);
    ImageF img = gaussian_blur(synth::render_tag(50, 50, tag_cells(f, id), H, 0.5f, 8, 0.42f, 0.58f), 1.1);
    for (auto& v : img.data) v += noise(rng);
    const auto r = read_payload_area(img, H, 6);
    if (!r || f.decode(r->bits, 3) || !soft_decode(f, *r)) continue;
    check(img, q, id);
    ++checked;
  }
  return checked;
}
}  // namespace

// The guard against slivers (SoftDecodeOptions::min_area_ratio): area over mean side squared is 1 for
// a square, about 0.5 for one seen at 80 degrees, 0 for a degenerate quad; a quad under the ratio is
// not soft decoded by decode_quads, one at or over it is.
TEST(SoftDecode, FlatQuadsAreNotSoftDecodedUnderTheAreaRatio) {
  using V = Eigen::Vector2d;
  EXPECT_NEAR(quad_area_ratio({V(0, 0), V(10, 0), V(10, 10), V(0, 10)}), 1.0, 1e-12);
  const double c = std::cos(80.0 * std::acos(-1.0) / 180);
  EXPECT_NEAR(quad_area_ratio({V(0, 0), V(10, 0), V(10, 10 * c), V(0, 10 * c)}), c / std::pow((1 + c) / 2, 2), 1e-12);
  EXPECT_EQ(quad_area_ratio({V(0, 0), V(10, 0), V(20, 0), V(30, 0)}), 0.0);
  EXPECT_EQ(quad_area_ratio({V(1, 1), V(1, 1), V(1, 1), V(1, 1)}), 0.0);

  // A tag only the soft decoder reads (as in the test above), through decode_quads.
  const std::vector<TagFamily> families{builtin_family("36h11")};
  PayloadAreaOptions area;
  SoftDecodeOptions soft;
  const auto square = [](int id) { return synth::square_tag_corners(25.2 + 0.11 * id, 24.7, 20.0, 0.13 * id); };
  const int checked = for_soft_only_tags(17, 60, 2, square, [&](const ImageF& img, const Quad& q, int id) {
    soft.min_area_ratio = 0;
    const auto yes = decode_quads(img, std::span(&q, 1), families, 3, PayloadOptions{}, &area, nullptr, nullptr, true, &soft);
    ASSERT_EQ(yes.size(), 1u);
    EXPECT_EQ(yes[0].id, id);
    soft.min_area_ratio = 0.99 * quad_area_ratio(q.corners);
    EXPECT_EQ(decode_quads(img, std::span(&q, 1), families, 3, PayloadOptions{}, &area, nullptr, nullptr, true, &soft).size(), 1u);
    soft.min_area_ratio = 1.01 * quad_area_ratio(q.corners);
    EXPECT_TRUE(decode_quads(img, std::span(&q, 1), families, 3, PayloadOptions{}, &area, nullptr, nullptr, true, &soft).empty());
  });
  EXPECT_EQ(checked, 2);
}

// The guard against quads no distant square gives (SoftDecodeOptions::min_opposite_ratio): the
// shorter of each pair of opposite sides over the longer, the smaller pair's; a tag rendered through a
// trapezoid (top 20 px, bottom 15 px: 0.75) that only the soft decoder reads is soft decoded under a
// bound of 0.7 and not under 0.8.
TEST(SoftDecode, QuadsWhoseOppositeSidesDifferAreNotSoftDecodedUnderTheRatio) {
  using V = Eigen::Vector2d;
  EXPECT_NEAR(quad_opposite_ratio({V(0, 0), V(10, 0), V(10, 10), V(0, 10)}), 1.0, 1e-12);
  EXPECT_NEAR(quad_opposite_ratio({V(0, 0), V(10, 0), V(13, 6), V(3, 6)}), 1.0, 1e-12);  // a parallelogram
  EXPECT_NEAR(quad_opposite_ratio({V(0, 0), V(20, 0), V(17.5, 10), V(2.5, 10)}), 0.75, 1e-12);
  EXPECT_EQ(quad_opposite_ratio({V(1, 1), V(1, 1), V(1, 1), V(1, 1)}), 0.0);

  const std::vector<TagFamily> families{builtin_family("36h11")};
  PayloadAreaOptions area;
  SoftDecodeOptions soft;
  const Corners trapezoid = {V(15, 15), V(35, 15), V(32.5, 35), V(17.5, 35)};
  ASSERT_NEAR(quad_opposite_ratio(trapezoid), 0.75, 1e-12);
  const int checked = for_soft_only_tags(23, 300, 2, [&](int) { return trapezoid; }, [&](const ImageF& img, const Quad& q, int id) {
    soft.min_opposite_ratio = 0.7;
    const auto yes = decode_quads(img, std::span(&q, 1), families, 3, PayloadOptions{}, &area, nullptr, nullptr, true, &soft);
    ASSERT_EQ(yes.size(), 1u);
    EXPECT_EQ(yes[0].id, id);
    soft.min_opposite_ratio = 0.8;
    EXPECT_TRUE(decode_quads(img, std::span(&q, 1), families, 3, PayloadOptions{}, &area, nullptr, nullptr, true, &soft).empty());
  });
  EXPECT_EQ(checked, 2);
}

}  // namespace test_soft_decode
