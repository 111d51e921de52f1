// Stages 1-5 as one function: the same quads as the stage functions composed by hand, the
// decoding image, the workspace's buffers reused, the trace and the counts.
#include <gtest/gtest.h>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/find_quads_in_image.hpp"
#include "detect/gradient.hpp"
#include "detect/segmentation.hpp"
#include "synthetic_tag.hpp"

namespace test_find_quads_in_image {

using namespace tagbench;

namespace {

ImageF tag_image() {
  const Corners truth = synth::square_tag_corners(110, 95, 90, 0.4);
  return synth::render_tag(220, 190, tag_cells(builtin_family("25h9"), 3), synth::homography_for(truth));
}

// The stages composed by hand from the allocating functions.
FoundQuads by_hand(const ImageF& gray, const DetectorOptions& o) {
  const bool halve = o.half_resolution && gray.width >= 4 && gray.height >= 4;
  const ImageF seg_in = halve ? blur_and_halve(gray, o.seg_sigma) : gaussian_blur(gray, o.seg_sigma);
  const Gradients g = compute_gradients(seg_in, o.segmentation.min_mag);
  FoundQuads r;
  r.segments = fit_segments(segment_clusters(g, o.segmentation), o.line_fit);
  if (halve)
    for (auto& s : r.segments) s = segment_full_from_half(s);
  r.quads = find_quads(r.segments, o.quad_search);
  return r;
}

void expect_same(const FoundQuads& a, const FoundQuads& b) {
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].p0, b.segments[i].p0);
    EXPECT_EQ(a.segments[i].p1, b.segments[i].p1);
  }
  ASSERT_EQ(a.quads.size(), b.quads.size());
  for (std::size_t i = 0; i < a.quads.size(); ++i) {
    EXPECT_EQ(a.quads[i].corners, b.quads[i].corners);
    EXPECT_EQ(a.quads[i].segments, b.quads[i].segments);
    EXPECT_EQ(a.quads[i].observed_perimeter, b.quads[i].observed_perimeter);
  }
}

}  // namespace

TEST(FindQuadsInImage, EqualsTheStagesComposedByHand) {
  const ImageF img = tag_image();
  for (const bool half : {false, true}) {
    DetectorOptions o;
    o.half_resolution = half;
    DetectorWorkspace ws;
    const FoundQuads got = find_quads_in_image(img, o, ws);
    EXPECT_FALSE(got.quads.empty()) << half;
    expect_same(got, by_hand(img, o));
    EXPECT_EQ(got.decode_image, &img);  // decode_sigma 0: payloads are read from the input itself
  }
}

TEST(FindQuadsInImage, DecodeImageIsTheSeparatelyBlurredCopy) {
  const ImageF img = tag_image();
  DetectorOptions o;
  o.decode_sigma = 1.5;
  DetectorWorkspace ws;
  const FoundQuads got = find_quads_in_image(img, o, ws);
  ASSERT_NE(got.decode_image, &img);
  EXPECT_EQ(got.decode_image->data, gaussian_blur(img, 1.5).data);
  expect_same(got, by_hand(img, o));  // the segmentation does not see decode_sigma
}

TEST(FindQuadsInImage, ReusesTheWorkspaceAndFillsTimingsAndTrace) {
  const ImageF img = tag_image();
  const DetectorOptions o;
  DetectorWorkspace ws;
  const FoundQuads first = find_quads_in_image(img, o, ws);
  const auto buffers = ws.buffers();
  StageTimings tm;
  tm.decode = 7;  // not one of this function's fields: left alone
  DetectorTrace trace;
  const FoundQuads second = find_quads_in_image(img, o, ws, &tm, &trace);
  expect_same(first, second);
  const auto again = ws.buffers();
  ASSERT_EQ(again.size(), buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    EXPECT_EQ(again[i].data, buffers[i].data) << buffers[i].name;
    EXPECT_EQ(again[i].capacity_bytes, buffers[i].capacity_bytes) << buffers[i].name;
  }
  EXPECT_EQ(tm.segment_count, second.segments.size());
  EXPECT_EQ(tm.quad_count, second.quads.size());
  EXPECT_EQ(tm.decode, 7);
  EXPECT_GE(tm.blur, 0);
  EXPECT_EQ(trace.segmentation_input.data, gaussian_blur(img, o.seg_sigma).data);
  EXPECT_EQ(trace.gradient_magnitude.data, compute_gradients(trace.segmentation_input, o.segmentation.min_mag).mag);
  EXPECT_GT(trace.clusters.size(), 0u);
  FoundQuads traced;
  traced.segments = trace.segments;
  traced.quads = trace.quads;
  expect_same(traced, second);
  EXPECT_TRUE(trace.readings.empty());  // decoding is not this function's
}

}  // namespace test_find_quads_in_image
