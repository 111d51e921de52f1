// The detector profiles (detector_options.hpp): DetectorOptions::paper() and the default profile, and the
// default profile's quad finder alone (find_threshold_quads_in_image.hpp).
#include <gtest/gtest.h>

#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/detector.hpp"
#include "detect/find_threshold_quads_in_image.hpp"
#include "synthetic_tag.hpp"

namespace test_profiles {

using namespace tagbench;

namespace {

// Tags of `side` px, one per 48 px cell of a 4 x 3 grid, blurred and noisy like a small camera image.
struct Scene {
  ImageF img;
  std::vector<int> ids;
};
Scene small_tags(double side, std::uint32_t seed, double blur_sigma = 0.8) {
  const TagFamily& f = builtin_family("36h11");
  Scene s{ImageF(192, 144, 0.55f), {}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int gy = 0; gy < 3; ++gy)
    for (int gx = 0; gx < 4; ++gx) {
      const int id = 7 * (gy * 4 + gx) + 3;
      const Corners c = synth::square_tag_corners(24 + 48 * gx + u(rng), 24 + 48 * gy + u(rng), side, 0.4 * gx + u(rng));
      const ImageF t = synth::render_tag(192, 144, tag_cells(f, id), synth::homography_for(c));
      // Copy the tag's neighbourhood (its own cell of the grid) into the scene.
      for (int y = 48 * gy; y < 48 * gy + 48; ++y)
        for (int x = 48 * gx; x < 48 * gx + 48; ++x) s.img.at(x, y) = t.at(x, y);
      s.ids.push_back(id);
    }
  s.img = gaussian_blur(s.img, blur_sigma);
  std::normal_distribution<float> noise(0.0f, 0.02f);
  for (auto& v : s.img.data) v = std::clamp(v + noise(rng), 0.0f, 1.0f);
  return s;
}

int found_ids(const std::vector<Detection>& dets, const std::vector<int>& ids) {
  int n = 0;
  for (int id : ids)
    n += std::count_if(dets.begin(), dets.end(), [&](const Detection& d) { return d.id == id; }) > 0;
  return n;
}

}  // namespace

TEST(Profiles, PaperPresetIsThePapersComposition) {
  const DetectorOptions p = DetectorOptions::paper(), d;
  EXPECT_EQ(p.quad_finder, QuadFinderKind::kGradient);
  EXPECT_EQ(p.payload_reader, PayloadReaderKind::kPoint);
  EXPECT_EQ(d.quad_finder, QuadFinderKind::kThreshold);
  EXPECT_EQ(d.payload_reader, PayloadReaderKind::kArea);
  EXPECT_FALSE(p.photometric.enabled);
  EXPECT_TRUE(d.photometric.enabled);
  EXPECT_EQ(p.max_hamming, 1);  // the Java default, every family
  EXPECT_FALSE(p.hamming_by_family);
  EXPECT_EQ(d.max_hamming, 3);  // capped per family at (h - 1) / 3
  EXPECT_TRUE(d.hamming_by_family);
  EXPECT_EQ(p.seg_sigma, 0.8);
  EXPECT_FALSE(p.second_look.enabled);
  EXPECT_FALSE(p.group_look.enabled);
  EXPECT_TRUE(d.second_look.enabled);
  EXPECT_FALSE(p.soft_decode.enabled);
  EXPECT_TRUE(d.soft_decode.enabled);
  EXPECT_FALSE(p.suppress_overlaps);
  EXPECT_TRUE(d.suppress_overlaps);
  EXPECT_TRUE(DetectorOptions::thorough().suppress_overlaps);
  EXPECT_FALSE(p.linear_corners.enabled);
  EXPECT_TRUE(d.linear_corners.enabled);
  EXPECT_TRUE(DetectorOptions::thorough().linear_corners.enabled);
  EXPECT_TRUE(d.threshold_quads.noise_blur.enabled);  // a blur for sharpened or noisy photographs
  EXPECT_EQ(d.soft_decode.min_area_ratio, 0.4);        // and no soft decoding of slivers with it
  EXPECT_EQ(d.soft_decode.min_opposite_ratio, 0.8);    // nor of quads no distant square gives
  EXPECT_EQ(d.threshold_quads.fit.outer.ring_outward_slack, 1.0 / 16);  // a side a pixel inside the edge
  EXPECT_EQ(d.threshold_quads.fit.outer.ring_slack_sides, 1);           // on at most one side
  EXPECT_EQ(d.input_gamma, 1.0);  // the image as it is unless told its encoding (a wrong gamma costs most)
  p.validate();
  d.validate();
}

// The thorough profile is the default with its line quads at full resolution (LineQuadOptions' own
// defaults) and the coarse pass on, nothing else changed: with those set back it detects exactly
// what the default does.
TEST(Profiles, ThoroughIsTheDefaultWithFullResolutionLineQuadsAndTheCoarsePass) {
  const DetectorOptions t = DetectorOptions::thorough(), d;
  EXPECT_TRUE(t.line_quads.enabled);
  EXPECT_TRUE(d.line_quads.enabled);
  EXPECT_EQ(t.line_quads.scale, 1.0);
  EXPECT_EQ(d.line_quads.scale, 0.5);
  EXPECT_FALSE(d.line_quads.at_half_resolution);
  EXPECT_TRUE(t.line_quads.at_half_resolution);
  EXPECT_TRUE(t.coarse_pass.enabled);
  EXPECT_FALSE(d.coarse_pass.enabled);
  t.validate();
  DetectorOptions back = t;
  back.line_quads = d.line_quads;
  back.coarse_pass.enabled = false;
  const Detector a(d), b(back), c(t);
  int found = 0, total = 0;
  for (std::uint32_t seed = 1; seed <= 2; ++seed) {
    const Scene s = small_tags(14.0, seed);
    const auto x = a.detect(s.img), y = b.detect(s.img), z = c.detect(s.img);
    ASSERT_EQ(x.size(), y.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_EQ(x[i].id, y[i].id);
      for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(x[i].corners[k], y[i].corners[k]);
    }
    found += found_ids(z, s.ids);
    total += static_cast<int>(s.ids.size());
    for (const Detection& det : z) EXPECT_NE(std::find(s.ids.begin(), s.ids.end(), det.id), s.ids.end()) << det.id;
  }
  EXPECT_GE(found, total * 9 / 10);
}

// The names the command line and Python use.
TEST(Profiles, NamedProfiles) {
  EXPECT_EQ(DetectorOptions::named_profile("default")->line_quads.scale, 0.5);
  EXPECT_EQ(DetectorOptions::named_profile("default")->quad_finder, QuadFinderKind::kThreshold);
  EXPECT_EQ(DetectorOptions::named_profile("thorough")->line_quads.scale, 1.0);
  EXPECT_EQ(DetectorOptions::named_profile("paper")->quad_finder, QuadFinderKind::kGradient);
  EXPECT_FALSE(DetectorOptions::named_profile("fast").has_value());
  EXPECT_FALSE(DetectorOptions::named_profile("").has_value());
}

// Small tags (black square 14 px, cells 1.75 px) with blur and noise: the default profile finds
// (nearly) all of them, the paper's detector few, and neither reports a wrong id.
TEST(Profiles, DefaultProfileFindsSmallTagsThePaperMisses) {
  int paper_found = 0, default_found = 0, total = 0;
  const Detector paper(DetectorOptions::paper()), dflt(DetectorOptions{});
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const Scene s = small_tags(14.0, seed);
    const auto a = paper.detect(s.img), b = dflt.detect(s.img);
    paper_found += found_ids(a, s.ids);
    default_found += found_ids(b, s.ids);
    total += static_cast<int>(s.ids.size());
    for (const auto* v : {&a, &b})
      for (const Detection& d : *v) EXPECT_NE(std::find(s.ids.begin(), s.ids.end(), d.id), s.ids.end()) << d.id;
  }
  EXPECT_GE(default_found, total * 9 / 10) << "paper " << paper_found;
  EXPECT_GE(default_found, paper_found + total / 4);
}

// Tags at the edge of range (issue 17): black square 10 px (cells 1.25 px), rotated 0..70 degrees,
// under noise of 5 grey levels. The default profile finds nearly all of them; with dark regions
// 4-connected (AprilTag 3's pairing, dark_eight_connected off) the one-pixel border breaks apart and
// far fewer are found. (The noise engages the default's threshold blur, noise_blur: 32 -> 31 of 36
// here, while on the realistic set's noisiest variant it finds more of the tags under 12 px, 30 vs 25
// of 795, session 34; hence 5/6 and not 9/10.)
TEST(Profiles, DefaultProfileFindsTenPixelTags) {
  int found8 = 0, found4 = 0, total = 0;
  DetectorOptions four;
  four.threshold_quads.dark_eight_connected = false;
  const Detector dflt(DetectorOptions{}), dark4(four);
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const Scene s = small_tags(10.0, seed, 0.5);
    const auto a = dflt.detect(s.img), b = dark4.detect(s.img);
    found8 += found_ids(a, s.ids);
    found4 += found_ids(b, s.ids);
    total += static_cast<int>(s.ids.size());
    for (const auto* v : {&a, &b})
      for (const Detection& d : *v) EXPECT_NE(std::find(s.ids.begin(), s.ids.end(), d.id), s.ids.end()) << d.id;
  }
  EXPECT_GE(found8, total * 5 / 6) << "4-connected " << found4;
  EXPECT_GE(found8, found4 + total / 6) << "4-connected " << found4;
}

// The threshold finder alone: one quad per tag, corners within a fifth of a pixel after refinement,
// in full-resolution coordinates also at half resolution; its timings and trace are filled.
TEST(FindThresholdQuadsInImage, QuadsOfLargeTagsAtFullAndHalfResolution) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(60.3, 50.8, 48.0, 0.3);
  const ImageF img = gaussian_blur(synth::render_tag(120, 100, tag_cells(f, 4), synth::homography_for(truth)), 0.6);
  for (bool half : {false, true}) {
    DetectorOptions o;
    o.half_resolution = half;
    DetectorWorkspace ws;
    StageTimings tm;
    DetectorTrace trace;
    const FoundQuads q = find_threshold_quads_in_image(img, o, ws, &tm, &trace);
    EXPECT_EQ(q.decode_image, &img);
    EXPECT_TRUE(q.segments.empty());
    EXPECT_EQ(tm.quad_count, q.quads.size());
    EXPECT_EQ(trace.quads.size(), q.quads.size());
    EXPECT_DOUBLE_EQ(trace.segmentation_scale, half ? 2.0 : 1.0);
    int near = 0;
    for (const Quad& quad : q.quads) {
      double best = 1e9;
      for (std::size_t r = 0; r < 4; ++r) {
        double e = 0;
        for (std::size_t i = 0; i < 4; ++i) e = std::max(e, (quad.corners[(i + r) % 4] - truth[i]).norm());
        best = std::min(best, e);
      }
      near += best < 0.2;
    }
    EXPECT_EQ(near, 1) << "half " << half;
  }
}

}  // namespace test_profiles
