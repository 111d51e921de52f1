#pragma once
// tagbench detect --explain X,Y[,FAMILY:ID]: why no tag was reported at pixel (X, Y) of an image
// (issue 17, section 2), from the detection's trace (DetectorTrace with quad_outcomes):
//   1. a detection whose quad holds the point: "detected" (with FAMILY:ID of another id: wrong_id);
//   2. else the candidate quads that hold the point, the one that got furthest (then the one centred
//      nearest the point: give the tag's centre):
//      without FAMILY:ID its outcome: quad_rejected (border pre-filter, degenerate corners, unreadable
//      cells), misread (read, no family decoded it), below_margin, withdrawn (by the occlusion refit) or
//      duplicate (decoded, not reported);
//      with FAMILY:ID, explain_loss (detect/explain_loss.hpp) with that quad as the tag's place, in the
//      printed orientation that fits best: also the bits of the tag's code read wrong, wrong_id;
//   3. else, near the point (kExplainRadiusPx): segments but no quad around it: no_quad; gradient
//      clusters but no segment: no_segment; neither: no_cluster. The threshold quad finder has no
//      segments or clusters: no_quad, with its pixel classes and boundary groups within kExplainNearPx.
// Pixel centres at integer coordinates.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "codes/tag_family.hpp"
#include "detect/detector.hpp"

namespace tagbench::cli::detect_cmd {

// How far from the point segments and gradient pixels count as "near it" when no quad holds it.
inline constexpr double kExplainRadiusPx = 50;
// With the threshold quad finder (the default profile), the neighbourhood whose pixel classes and
// boundary groups the no_quad explanation reports (DetectorTrace::threshold_classes, boundary_groups).
inline constexpr double kExplainNearPx = 10;

struct ExplainPoint {
  std::string spec;                 // as given, "X,Y[,FAMILY:ID]"
  Eigen::Vector2d at{0, 0};
  std::optional<TagFamily> family;  // with FAMILY:ID
  int id = -1;
};

// Parses "X,Y" or "X,Y,FAMILY:ID" (FAMILY a built-in name or a family file, ID in it); throws
// UsageError (args.hpp) with one line.
ExplainPoint parse_explain_point(const std::string& text);

struct PointExplanation {
  std::string spec;
  Eigen::Vector2d at{0, 0};
  std::string stage;         // a loss_stage_name word, "detected" or (set by the caller) "outside_image"
  int bits_wrong = -1;       // with FAMILY:ID, misread / wrong_id: bits of its code read wrong
  int quad = -1;             // the candidate quad that speaks for the point (index in the trace), or -1
  std::string text;          // one line for people
};

// `trace` and `detections` from one detect() call of `detector`.
PointExplanation explain_point(const ExplainPoint& p, const DetectorTrace& trace,
                               const std::vector<Detection>& detections, const Detector& detector);

// {"at": [x, y], "given": "X,Y[,FAMILY:ID]", "stage", "bits_wrong": n or null, "quad": i or null, "text"}
std::string explanation_json(const PointExplanation& e);

}  // namespace tagbench::cli::detect_cmd
