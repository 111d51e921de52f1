// The scorer (issue 12, section 2): detections equal to the truth score zero error; a foreign
// convention, declared, scores as ours; undeclared, the one-line hint names the options that fix it;
// every malformed input is one line naming the source, line and image.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "score/score.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {
namespace test_score {
namespace {

Dataset small_dataset() {
  SweepSettings s;
  s.trials = 3;
  s.steps = {0, 30};
  s.detectors = {comparator_names().front()};
  s = resolve_settings(s);
  Dataset d;
  d.settings = s;
  d.settings.detectors.clear();
  const auto plan = plan_sweep(s);
  for (std::size_t i = 0; i < plan.size(); ++i) d.frames.push_back({dataset_frame_file(i), i, plan[i], std::nullopt});
  return d;
}

std::string point(const Eigen::Vector2d& p) { return std::string("[") + json_number(p.x()) + ", " + json_number(p.y()) + "]"; }

// A line with the frame's truth written in a detector's convention (corners permuted and shifted, R
// turned into its tag frame), or no detection when `found` is false.
std::string line(const DatasetFrame& f, const Convention& c, bool found = true, int id_offset = 0) {
  std::string s = "{\"image\": " + json_string(f.file) + ", \"ms\": 2.5, \"detections\": [";
  if (found) {
    const GroundTruth& t = f.frame.truth;
    s += "{\"family\": \"tag36h11\", \"id\": " + std::to_string(f.frame.frame.id + id_offset) + ", \"corners\": [";
    for (std::size_t k = 0; k < 4; ++k)
      s += (k ? ", " : "") + point(t.corners[static_cast<std::size_t>(c.order[k])] + Eigen::Vector2d::Constant(c.pixel_offset));
    const Eigen::Matrix3d R = t.pose.R * c.tag_axes.transpose();
    s += "], \"pose\": {\"R\": [";
    for (int i = 0; i < 3; ++i)
      s += std::string(i ? ", " : "") + "[" + json_number(R(i, 0)) + ", " + json_number(R(i, 1)) + ", " +
           json_number(R(i, 2)) + "]";
    s += "], \"t\": [" + json_number(t.pose.t.x()) + ", " + json_number(t.pose.t.y()) + ", " + json_number(t.pose.t.z()) + "]}}";
  }
  return s + "]}\n";
}

std::string all_lines(const Dataset& d, const Convention& c) {
  std::string text;
  for (std::size_t i = d.frames.size(); i-- > 0;) text += line(d.frames[i], c, i != 1);  // any order; frame 1 missed
  return text;
}

TEST(Score, TruthScoresZeroAndAMissAsMissed) {
  const Dataset d = small_dataset();
  const Convention ours;
  const ScoreResult r = score_detections(d, ".", parse_detection_lines(all_lines(d, ours), "det.jsonl"), "det.jsonl", "mine", ours);
  ASSERT_EQ(r.sweep.rows.size(), d.frames.size());
  for (std::size_t i = 0; i < r.sweep.rows.size(); ++i) {
    const SweepRow& row = r.sweep.rows[i];
    EXPECT_EQ(row.frame, i);
    EXPECT_EQ(row.detector, "mine");
    EXPECT_EQ(row.detected_right_id, i != 1);
    EXPECT_FALSE(row.wrong_id);
    EXPECT_EQ(row.ms, 2.5);
    if (i != 1) {
      EXPECT_LT(row.corner_rms_px, 1e-9);
      EXPECT_LT(row.orientation_error_deg, 1e-4);
    }
  }
  EXPECT_TRUE(r.hint.empty()) << r.hint;
  const auto summary = summarize(r.sweep);
  ASSERT_EQ(summary.size(), 2u);
  EXPECT_EQ(summary[0].detected, 2);
  EXPECT_EQ(summary[0].frames, 3);
  EXPECT_NEAR(summary[0].rate_lo95, 0.2077, 1e-4);  // Wilson, 2 of 3
  EXPECT_NE(rows_csv(r.sweep).find(",mine,1,0,"), std::string::npos);
}

TEST(Score, AWrongIdIsMarked) {
  const Dataset d = small_dataset();
  std::string text;
  for (const auto& f : d.frames) text += line(f, {}, true, 1);
  const ScoreResult r = score_detections(d, ".", parse_detection_lines(text, "x"), "x", "mine", {});
  for (const auto& row : r.sweep.rows) {
    EXPECT_FALSE(row.detected_right_id);
    EXPECT_TRUE(row.wrong_id);
  }
}

TEST(Score, AForeignConventionDeclaredScoresAsOursAndUndeclaredIsNamed) {
  const Dataset d = small_dataset();
  Convention foreign;  // libapriltag's corners, aruco's marker frame
  foreign.order = parse_corner_order("bl-br-tr-tl");
  foreign.pixel_offset = 0.5;
  foreign.tag_axes = parse_tag_frame("-x,y,-z");
  const auto lines = parse_detection_lines(all_lines(d, foreign), "f.jsonl");
  const ScoreResult declared = score_detections(d, ".", lines, "f.jsonl", "f", foreign);
  for (const auto& row : declared.sweep.rows)
    if (row.detected_right_id) {
      EXPECT_LT(row.corner_rms_px, 1e-9);
      EXPECT_LT(row.orientation_error_deg, 1e-4);
    }
  EXPECT_TRUE(declared.hint.empty()) << declared.hint;
  const ScoreResult undeclared = score_detections(d, ".", lines, "f.jsonl", "f", {});
  EXPECT_EQ(undeclared.hint.substr(0, undeclared.hint.find(" (")),
            "f fits the truth far better declared with --corner-order bl-br-tr-tl --pixel-offset 0.5 --tag-frame -x,y,-z");
  // A corner order only rotated: that alone is named.
  Convention rotated;
  rotated.order = parse_corner_order("tr-br-bl-tl");
  const ScoreResult r = score_detections(d, ".", parse_detection_lines(all_lines(d, rotated), "r"), "r", "r", {});
  EXPECT_EQ(r.hint.substr(0, r.hint.find(" (")), "r fits the truth far better declared with --corner-order tr-br-bl-tl");
  // Half declared: the hint names the whole declaration that fits.
  Convention half = foreign;
  half.pixel_offset = 0;
  const ScoreResult h = score_detections(d, ".", lines, "f.jsonl", "f", half);
  EXPECT_EQ(h.hint.substr(0, h.hint.find(" (")), "f fits the truth far better declared with --pixel-offset 0.5");
}

TEST(Score, ConventionNamesRoundTripAndBadOnesAreRefused) {
  for (const char* o : {"tl-tr-br-bl", "bl-br-tr-tl", "br-bl-tl-tr"}) EXPECT_EQ(corner_order_name(parse_corner_order(o)), o);
  for (const char* a : {"x,y,z", "-x,y,-z", "y,-x,z"}) EXPECT_EQ(tag_frame_name(parse_tag_frame(a)), a);
  for (const char* o : {"tl-tr-br", "tl-tl-br-bl", "tl-tr-br-bl-tl", "top-tr-br-bl", ""})
    EXPECT_THROW(parse_corner_order(o), std::invalid_argument) << o;
  for (const char* a : {"x,y", "x,x,z", "-x,y,z", "x,y,w", "x,y,z,"}) EXPECT_THROW(parse_tag_frame(a), std::invalid_argument) << a;
}

std::string error_of(const Dataset& d, const std::string& text) {
  try {
    score_detections(d, "/data/ds", parse_detection_lines(text, "det.jsonl"), "det.jsonl", "n", {});
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Score, EveryFaultIsOneLineNamingTheImage) {
  const Dataset d = small_dataset();
  std::string good;
  for (const auto& f : d.frames) good += line(f, {});
  EXPECT_EQ(error_of(d, good), "accepted");
  std::string missing = good.substr(good.find('\n') + 1);
  EXPECT_EQ(error_of(d, missing),
            "det.jsonl: no line for image 'frame_00000.png' (1 of 6 frames have none; every frame needs a line, "
            "\"detections\": [] when nothing was found)");
  EXPECT_EQ(error_of(d, good + line(d.frames[2], {})),
            "det.jsonl line 7: image 'frame_00002.png' given twice (lines 3 and 7)");
  EXPECT_EQ(error_of(d, good + "{\"image\": \"frame_99999.png\", \"detections\": []}\n"),
            "det.jsonl line 7: image 'frame_99999.png' is not a frame of the dataset");
  EXPECT_EQ(error_of(d, "{\"image\": \"/elsewhere/frame_00000.png\", \"detections\": []}\n" + missing),
            "det.jsonl line 1: image '/elsewhere/frame_00000.png' is not in the dataset folder /data/ds");
  EXPECT_EQ(error_of(d, "{\"image\": \"/data/ds/frame_00000.png\", \"detections\": []}\n" + missing), "accepted");
  EXPECT_EQ(error_of(d, "{\"image\": \"frame_00000.png\", \"error\": \"cannot read\"}\n" + missing),
            "det.jsonl line 1: image 'frame_00000.png': the detector failed: cannot read");
  EXPECT_EQ(error_of(d, good + "{\"image\": \"frame_00000.png\", \"detections\": [\n"),
            "det.jsonl line 7: at byte 44: unexpected end of the text");
  EXPECT_EQ(error_of(d, "{\"image\": \"frame_00000.png\", \"detections\": [{\"family\": \"36h11\", \"id\": 1, "
                        "\"corners\": [[1, 2], [3, 4], [5, 6]]}]}\n"),
            "det.jsonl line 1: detections[0]: corners: expected 4 points [x, y]");
  EXPECT_EQ(error_of(d, "{\"detections\": []}\n"), "det.jsonl line 1: the line: no member 'image'");
  EXPECT_EQ(error_of(d, "{\"image\": \"frame_00000.png\", \"ms\": -5, \"detections\": []}\n"),
            "det.jsonl line 1: ms: -5.000000 is negative (milliseconds)");
  EXPECT_EQ(error_of(d, "{\"image\": \"frame_00000.png\", \"detections\": [{\"family\": \"36h11\", \"id\": -7, "
                        "\"corners\": [[1, 2], [3, 4], [5, 6], [7, 8]]}]}\n"),
            "det.jsonl line 1: detections[0]: id: -7 is negative");
  const auto with_R = [](const std::string& R) {
    return "{\"image\": \"frame_00000.png\", \"detections\": [{\"family\": \"36h11\", \"id\": 1, "
           "\"corners\": [[1, 2], [3, 4], [5, 6], [7, 8]], \"pose\": {\"R\": " + R + ", \"t\": [0, 0, 1]}}]}\n";
  };
  EXPECT_EQ(error_of(d, with_R("[[2, 0, 0], [0, 2, 0], [0, 0, 2]]")),
            "det.jsonl line 1: detections[0]: pose.R: not a rotation (R^T R differs from I by 3.000000)");
  EXPECT_EQ(error_of(d, with_R("[[1e300, 0, 0], [0, 1e300, 0], [0, 0, 1e300]]")).substr(0, 57),
            "det.jsonl line 1: detections[0]: pose.R: not a rotation (");
  // Six significant digits of a rotation (0.6, 0.8: 30 degrees' neighbour) pass.
  EXPECT_NE(error_of(d, with_R("[[0.600000, -0.800000, 0], [0.800000, 0.600000, 0], [0, 0, 1]]")).find("no line for"),
            std::string::npos);
}

}  // namespace
}  // namespace test_score
}  // namespace tagbench::bench
