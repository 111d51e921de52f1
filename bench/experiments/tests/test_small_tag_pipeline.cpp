#include <gtest/gtest.h>

#include <algorithm>

#include "codes/families.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/detector.hpp"
#include "experiments/small_tag_pipeline.hpp"
#include "scenes.hpp"

namespace test_small_tag_pipeline {

using namespace tagbench;
using namespace tagbench::bench;
using namespace tagbench::bench::experiments;

// The "paper" variant calls the stages as the detector wires them: the same ids and corners.
TEST(SmallTagPipeline, PaperVariantIsTheDetector) {
  for (const std::uint32_t seed : {3u, 8u}) {
    const Scene scene = make_scene(480, 360, "36h11", 5, seed);
    const ImageF gray = to_float_image(scene.image);
    const Detector detector(DetectorOptions::paper());
    const auto want = detector.detect(gray);
    const auto got = run_pipeline(gray, builtin_family("36h11"), Variant{});
    ASSERT_EQ(got.detections.size(), want.size()) << seed;
    ASSERT_GE(want.size(), 3u);
    for (const auto& w : want) {
      const auto it = std::find_if(got.detections.begin(), got.detections.end(),
                                   [&](const PipelineDetection& g) { return g.id == w.id; });
      ASSERT_NE(it, got.detections.end()) << w.id;
      for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((it->corners[i] - w.corners[i]).norm(), 1e-9);
      EXPECT_EQ(it->hamming, w.hamming);
    }
  }
}

// The improved variant finds the same tags on a clean scene, and refinement moves corners little.
TEST(SmallTagPipeline, RefinedVariantKeepsCleanSceneDetections) {
  const Scene scene = make_scene(480, 360, "36h11", 5, 3);
  const ImageF gray = to_float_image(scene.image);
  const auto v = parse_variant("best:refine=1,area=1");
  EXPECT_TRUE(v.refine_edges && v.area_payload);
  const auto got = run_pipeline(gray, builtin_family("36h11"), v);
  for (const auto& t : scene.tags) {
    const auto it = std::find_if(got.detections.begin(), got.detections.end(),
                                 [&](const PipelineDetection& g) { return g.id == t.id; });
    ASSERT_NE(it, got.detections.end()) << t.id;
    for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((it->corners[i] - t.corners[i]).norm(), 0.5) << t.id;
  }
}

TEST(SmallTagPipeline, BadVariantSpecsAreRefused) {
  EXPECT_THROW(parse_variant(":refine=1"), std::invalid_argument);
  EXPECT_THROW(parse_variant("x:refine"), std::invalid_argument);
  EXPECT_THROW(parse_variant("x:bogus=1"), std::invalid_argument);
  EXPECT_THROW(parse_variant("x:sigma=abc"), std::invalid_argument);
  const Variant v = parse_variant("x:sigma=0.4,h=2,sharp=0.3,k=2,extent=0.5,up=1,range=2");
  EXPECT_DOUBLE_EQ(v.seg_sigma, 0.4);
  EXPECT_EQ(v.max_hamming, 2);
  EXPECT_DOUBLE_EQ(v.area.sharpening, 0.3);
  EXPECT_EQ(v.area.samples_per_side, 2);
  EXPECT_TRUE(v.upsample);
}

}  // namespace test_small_tag_pipeline
