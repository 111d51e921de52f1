#include "detect/explain_loss.hpp"

#include <gtest/gtest.h>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "synthetic_tag.hpp"

namespace tagbench {
namespace test_explain_loss {
namespace {

DetectorOptions opts(const std::string& family, int max_hamming = 1) {
  DetectorOptions o = DetectorOptions::paper();
  o.families = {family};
  o.max_hamming = max_hamming;
  return o;
}

struct Traced {
  DetectorTrace trace;
  std::vector<Detection> dets;
};

Traced run_traced(const DetectorOptions& o, const ImageF& img) {
  Traced r;
  r.dets = Detector(o).detect(img, &r.trace);
  return r;
}

TEST(ExplainLoss, DetectedTagSaysDetected) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(80, 80, 90, 0.3);
  const ImageF img = synth::render_tag(160, 160, tag_cells(f, 5), synth::homography_for(truth));
  const DetectorOptions o = opts("25h9");
  const Traced r = run_traced(o, img);
  ASSERT_EQ(r.trace.quad_outcomes.size(), r.trace.quads.size());
  const auto e = explain_loss({&f, 5, truth}, r.trace, r.dets, o);
  EXPECT_EQ(e.stage, LossStage::kDetected) << e.text;
  // Another id at the same place: the quad decoded as 5, so for id 6 it is a wrong id.
  const auto other = explain_loss({&f, 6, truth}, r.trace, r.dets, o);
  EXPECT_EQ(other.stage, LossStage::kWrongId) << other.text;
  EXPECT_GT(other.bits_wrong, 0);
  EXPECT_STREQ(loss_stage_name(other.stage), "wrong_id");
}

TEST(ExplainLoss, BitErrorsBeyondMaxHammingAreMisreadsWithTheirCount) {
  const TagFamily& f = builtin_family("36h15");
  const Corners truth = synth::square_tag_corners(80, 80, 100, 1.9);  // rotated: exercises the code's rotation
  TagCells cells = tag_cells(f, 4);
  for (int e = 0; e < 3; ++e) {
    const int y = 2 + (e * 5) % 6, x = 2 + (e * 3 + 1) % 6;
    cells.white[static_cast<std::size_t>(y * cells.n + x)] ^= 1;
  }
  const ImageF img = synth::render_tag(160, 160, cells, synth::homography_for(truth));
  const DetectorOptions o = opts("36h15", 1);
  const Traced r = run_traced(o, img);
  EXPECT_TRUE(r.dets.empty());
  const auto e = explain_loss({&f, 4, truth}, r.trace, r.dets, o);
  EXPECT_EQ(e.stage, LossStage::kMisread) << e.text;
  EXPECT_EQ(e.bits_wrong, 3);
  EXPECT_NE(e.text.find("3 bits wrong"), std::string::npos) << e.text;
}

TEST(ExplainLoss, MarginFilterAndBorderPrefilterAreNamed) {
  const TagFamily& f = builtin_family("16h5");
  const Corners truth = synth::square_tag_corners(70, 70, 80, 0.2);
  const ImageF img = synth::render_tag(140, 140, tag_cells(f, 3), synth::homography_for(truth));
  DetectorOptions o = opts("16h5", 0);
  o.min_decision_margin = 1.0;  // nothing real reaches a perfect margin
  const Traced r = run_traced(o, img);
  const auto e = explain_loss({&f, 3, truth}, r.trace, r.dets, o);
  EXPECT_EQ(e.stage, LossStage::kBelowMargin) << e.text;

  // A flat grey image with a quad planted in the trace: the border pre-filter refuses it.
  DetectorTrace t;
  t.quads.push_back(Quad{truth, {0, 1, 2, 3}, 320});
  t.quad_outcomes.push_back(QuadOutcome{});
  t.quad_outcomes.back().fate = QuadOutcome::Fate::kBorderRejected;
  const auto b = explain_loss({&f, 3, truth}, t, {}, opts("16h5"));
  EXPECT_EQ(b.stage, LossStage::kQuadRejected);
  EXPECT_NE(b.text.find("border pre-filter"), std::string::npos);
}

// A quad decoded right and not reported: withdrawn when the occlusion refit withdrew its detection
// (DetectorTrace::withdrawn), else a duplicate (another detection of the id was kept).
TEST(ExplainLoss, WithdrawnByTheOcclusionRefitIsToldFromADuplicate) {
  const TagFamily& f = builtin_family("16h5");
  const Corners truth = synth::square_tag_corners(70, 70, 80, 0.2);
  DetectorTrace t;
  t.quads.push_back(Quad{truth, {0, 1, 2, 3}, 320});
  QuadOutcome o;
  o.fate = QuadOutcome::Fate::kDecoded;
  o.family = "16h5";
  o.id = 3;
  o.hamming = 0;
  o.decision_margin = 0.8;
  o.bits[4] = f.codes()[3];
  t.quad_outcomes.push_back(o);
  const DetectorOptions opt = DetectorOptions{};
  const auto dup = explain_loss({&f, 3, truth}, t, {}, opt);
  EXPECT_EQ(dup.stage, LossStage::kDuplicate) << dup.text;
  Detection w;
  w.family = "16h5";
  w.id = 3;
  w.corners = truth;
  t.withdrawn.push_back(w);
  const auto e = explain_loss({&f, 3, truth}, t, {}, opt);
  EXPECT_EQ(e.stage, LossStage::kWithdrawn) << e.text;
  EXPECT_STREQ(loss_stage_name(e.stage), "withdrawn");
  EXPECT_NE(e.text.find("occlusion refit"), std::string::npos) << e.text;
  // A withdrawn detection of another id, or elsewhere, does not speak for this tag.
  t.withdrawn.back().id = 4;
  EXPECT_EQ(explain_loss({&f, 3, truth}, t, {}, opt).stage, LossStage::kDuplicate);
  t.withdrawn.back().id = 3;
  for (auto& c : t.withdrawn.back().corners) c += Eigen::Vector2d(30, 0);
  EXPECT_EQ(explain_loss({&f, 3, truth}, t, {}, opt).stage, LossStage::kDuplicate);
}

// A quad decoded within its family's correction but refused by its source's stricter limit (the
// line quads' spare bits) is a misread, with the bits of the tag's code read wrong.
TEST(ExplainLoss, AQuadTooFarForItsSourceIsAMisread) {
  const TagFamily& f = builtin_family("36h11");
  const Corners truth = synth::square_tag_corners(70, 70, 80, 0.2);
  DetectorTrace t;
  t.quads.push_back(Quad{truth, {0, 1, 2, 3}, 0});
  QuadOutcome o;
  o.fate = QuadOutcome::Fate::kTooFarForItsSource;
  o.family = "36h11";
  o.id = 9;
  o.hamming = 3;
  o.bits[6] = f.codes()[9] ^ Code{0b10101};  // three bits off: 36h11 corrects 3, the line quads 2
  t.quad_outcomes.push_back(o);
  const auto e = explain_loss({&f, 9, truth}, t, {}, DetectorOptions::thorough());
  EXPECT_EQ(e.stage, LossStage::kMisread) << e.text;
  EXPECT_EQ(e.bits_wrong, 3);
  EXPECT_NE(e.text.find("with 3 corrected, more than its quad's source accepts (the line quads: 1 fewer"),
            std::string::npos)
      << e.text;
}

TEST(ExplainLoss, MissingSidesAndClustersAreCounted) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(80, 80, 90, 0.0);
  const DetectorOptions o = opts("25h9");
  DetectorTrace t;  // a gradient trace: segments on two sides only
  t.segments.push_back(Segment{truth[1], truth[0], M_PI, (truth[1] - truth[0]).norm()});
  t.segments.push_back(Segment{truth[2], truth[1], -M_PI / 2, (truth[2] - truth[1]).norm()});
  const auto two = explain_loss({&f, 1, truth}, t, {}, o);
  EXPECT_EQ(two.stage, LossStage::kNoSegment);
  EXPECT_EQ(two.sides_with_segment, 2);
  t.segments.push_back(Segment{truth[3], truth[2], 0, (truth[3] - truth[2]).norm()});
  t.segments.push_back(Segment{truth[0], truth[3], M_PI / 2, (truth[0] - truth[3]).norm()});
  const auto four = explain_loss({&f, 1, truth}, t, {}, o);
  EXPECT_EQ(four.stage, LossStage::kNoQuad) << four.text;
  EXPECT_EQ(four.sides_with_segment, 4);
  // A segment across the tag's middle is along no side.
  DetectorTrace mid;
  mid.segments.push_back(Segment{Eigen::Vector2d(40, 80), Eigen::Vector2d(120, 80), 0, 80});
  EXPECT_EQ(explain_loss({&f, 1, truth}, mid, {}, o).stage, LossStage::kNoCluster);
  // Clusters along the border at half resolution (pixel x maps to 2x + 0.5) but no segment.
  DetectorTrace half;
  half.segmentation_scale = 2;
  half.segments.push_back(Segment{Eigen::Vector2d(0, 0), Eigen::Vector2d(5, 0), 0, 5});  // far away
  for (int x = 20; x < 30; ++x) half.clusters.pixels.push_back(ClusterPixel{x, static_cast<int>((truth[0].y() - 0.5) / 2)});
  half.clusters.offsets = {0, half.clusters.pixels.size()};
  EXPECT_EQ(explain_loss({&f, 1, truth}, half, {}, o).stage, LossStage::kNoSegment);
  // The threshold quad finder (the default profile) has no clusters or segments: it loses at no_quad.
  DetectorOptions threshold = DetectorOptions{};
  threshold.families = {"25h9"};
  ASSERT_EQ(threshold.quad_finder, QuadFinderKind::kThreshold);
  EXPECT_EQ(explain_loss({&f, 1, truth}, DetectorTrace{}, {}, threshold).stage, LossStage::kNoQuad);
  // The gradient finder with nothing at all in its trace (a frame without one cluster) loses at no_cluster:
  // the finder is told by the options, not guessed from the trace.
  EXPECT_EQ(explain_loss({&f, 1, truth}, DetectorTrace{}, {}, o).stage, LossStage::kNoCluster);
}

TEST(ExplainLoss, BadTruthIsRefused) {
  const TagFamily& f = builtin_family("16h5");
  EXPECT_THROW(explain_loss({nullptr, 0, {}}, DetectorTrace{}, {}, opts("16h5")), std::invalid_argument);
  EXPECT_THROW(explain_loss({&f, 99, {}}, DetectorTrace{}, {}, opts("16h5")), std::invalid_argument);
}

}  // namespace
}  // namespace test_explain_loss
}  // namespace tagbench
