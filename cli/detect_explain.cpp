#include "cli/detect_explain.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "cli/args.hpp"
#include "codes/families.hpp"
#include "detect/explain_loss.hpp"
#include "tools/json.hpp"

namespace tagbench::cli::detect_cmd {

namespace {

bool parse_number(const std::string& s, double& v) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(v);
}

// The point inside the quad (either winding), borders included.
bool inside(const Corners& c, const Eigen::Vector2d& p) {
  int pos = 0, neg = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = c[k], b = c[(k + 1) % 4];
    const double cross = (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
    if (cross > 0) ++pos;
    if (cross < 0) ++neg;
  }
  return pos == 0 || neg == 0;
}

double point_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// How far a quad's outcome got, for choosing among the quads that hold the point.
int progress(QuadOutcome::Fate f) {
  using F = QuadOutcome::Fate;
  switch (f) {
    case F::kBorderRejected: return 0;
    case F::kNoHomography: return 1;
    case F::kUnreadable: return 2;
    case F::kNotDecoded: return 3;
    case F::kTooFarForItsSource: return 4;
    case F::kDecoded: return 5;
  }
  return 0;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

// What the threshold quad finder saw near `at` (kExplainNearPx): its pixel classes and the boundary
// groups passing there, which tell a square joined to its surroundings (a group far larger than a
// tag), an outline split among groups, or a square and ring never classed apart (no group at all).
std::string threshold_near(const Eigen::Vector2d& at, const DetectorTrace& trace, const DetectorOptions& opt) {
  const TernaryImage& t = trace.threshold_classes;
  if (t.data.empty()) return "";
  const double s = trace.segmentation_scale, off = (s - 1) / 2;  // full-resolution x = s * x' + off
  const Eigen::Vector2d c = (at - Eigen::Vector2d(off, off)) / s;
  const double r = kExplainNearPx / s;
  std::size_t n = 0, dark = 0, light = 0;
  for (int y = std::max(0, static_cast<int>(std::floor(c.y() - r))); y <= std::min(t.height - 1, static_cast<int>(std::ceil(c.y() + r))); ++y)
    for (int x = std::max(0, static_cast<int>(std::floor(c.x() - r))); x <= std::min(t.width - 1, static_cast<int>(std::ceil(c.x() + r))); ++x) {
      if ((Eigen::Vector2d(x, y) - c).norm() > r) continue;
      ++n;
      dark += t.at(x, y) == kTernaryDark ? 1 : 0;
      light += t.at(x, y) == kTernaryLight ? 1 : 0;
    }
  if (n == 0) return "";
  const auto pct = [&](std::size_t k) { return std::to_string(static_cast<int>(std::lround(100.0 * static_cast<double>(k) / static_cast<double>(n)))); };
  std::string text = "; within " + num(kExplainNearPx) + " px: " + pct(dark) + " % of the pixels dark, " + pct(light) +
                     " % light, " + pct(n - dark - light) + " % too flat to class";
  const BoundaryGroups& g = trace.boundary_groups;
  std::size_t near = 0, fittable = 0;
  double largest = 0;
  std::string largest_box;
  for (std::size_t k = 0; k < g.count(); ++k) {
    const auto pts = g.group(k);
    const bool passes = std::any_of(pts.begin(), pts.end(), [&](const BoundaryPoint& q) {
      return (Eigen::Vector2d(q.x2 / 2.0, q.y2 / 2.0) - c).norm() <= r;
    });
    if (!passes) continue;
    ++near;
    fittable += pts.size() >= static_cast<std::size_t>(std::max(0, opt.threshold_quads.fit.min_points)) ? 1 : 0;
    const DoubledBox b = bounding_box(pts);
    // The points lie on pixel edges, so their span is the outline's extent (full-resolution px).
    const double w = s * (b.xmax - b.xmin) / 2, h = s * (b.ymax - b.ymin) / 2;
    if (w * h > largest) largest = w * h, largest_box = num(w) + " x " + num(h) + " px";
  }
  if (near == 0) return text + ", no boundary group";
  return text + ", " + std::to_string(near) + " boundary group" + (near == 1 ? "" : "s") + " (the largest " + largest_box +
         "; " + std::to_string(fittable) + " with enough points for the quad fit)";
}

}  // namespace

ExplainPoint parse_explain_point(const std::string& text) {
  const auto bad = [&](const std::string& why) { return UsageError("--explain " + text + ": " + why); };
  ExplainPoint p;
  p.spec = text;
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const auto comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (parts.size() != 2 && parts.size() != 3) throw bad("use X,Y or X,Y,FAMILY:ID");
  double x = 0, y = 0;
  if (!parse_number(parts[0], x) || !parse_number(parts[1], y)) throw bad("X and Y must be numbers (pixels)");
  p.at = {x, y};
  if (parts.size() == 3) {
    const auto colon = parts[2].rfind(':');
    if (colon == std::string::npos || colon == 0) throw bad("the tag is FAMILY:ID (e.g. 36h11:7)");
    const std::string fam = parts[2].substr(0, colon), id = parts[2].substr(colon + 1);
    try {
      p.family = load_family(fam);
    } catch (const std::exception& e) {
      throw bad(e.what());
    }
    int v = -1;
    const auto [end, ec] = std::from_chars(id.data(), id.data() + id.size(), v);
    if (ec != std::errc() || end != id.data() + id.size() || v < 0 || static_cast<std::size_t>(v) >= p.family->size())
      throw bad("id '" + id + "' is not in family " + p.family->name() + " (0.." +
                std::to_string(p.family->size() - 1) + ")");
    p.id = v;
  }
  return p;
}

PointExplanation explain_point(const ExplainPoint& p, const DetectorTrace& trace,
                               const std::vector<Detection>& detections, const Detector& detector) {
  PointExplanation out;
  out.spec = p.spec;
  out.at = p.at;
  const DetectorOptions& opt = detector.options();
  const std::string tag = p.family ? p.family->name() + " id " + std::to_string(p.id) : std::string();

  // 1. A detection there.
  const Detection* hit = nullptr;
  for (const Detection& d : detections)
    if (inside(d.corners, p.at) && (!hit || (p.family && d.family == p.family->name() && d.id == p.id))) hit = &d;
  if (hit && (!p.family || (hit->family == p.family->name() && hit->id == p.id))) {
    out.stage = "detected";
    out.text = "detected: " + hit->family + " id " + std::to_string(hit->id);
    return out;
  }

  // 2. The candidate quads that hold the point. Without FAMILY:ID the one that got furthest speaks,
  // then the one centred nearest the point (the tag's own quad, not quads inside its payload or
  // around it); with FAMILY:ID each is taken as the tag's place in each of its four printed
  // orientations (explain_loss), and the best fit speaks (furthest stage, fewest bits wrong, nearest).
  const auto centre_gap = [&](std::size_t i) {
    const Corners& c = trace.quads[i].corners;
    return ((c[0] + c[1] + c[2] + c[3]) / 4 - p.at).norm();
  };
  int best = -1;
  std::optional<LossExplanation> pick;
  for (std::size_t i = 0; i < trace.quads.size() && i < trace.quad_outcomes.size(); ++i) {
    if (!inside(trace.quads[i].corners, p.at)) continue;
    if (p.family) {
      for (std::size_t r = 0; r < 4; ++r) {
        Corners c;
        for (std::size_t k = 0; k < 4; ++k) c[k] = trace.quads[i].corners[(k + r) % 4];
        const LossExplanation e = explain_loss({&*p.family, p.id, c}, trace, detections, opt);
        bool better = !pick || e.stage > pick->stage;
        if (pick && e.stage == pick->stage) {
          if (e.bits_wrong >= 0 && pick->bits_wrong >= 0 && e.bits_wrong != pick->bits_wrong)
            better = e.bits_wrong < pick->bits_wrong;
          else
            better = centre_gap(i) < centre_gap(static_cast<std::size_t>(best));
        }
        if (better) {
          pick = e;
          best = static_cast<int>(i);
        }
      }
      continue;
    }
    if (best < 0) {
      best = static_cast<int>(i);
      continue;
    }
    const auto b = static_cast<std::size_t>(best);
    const int pi = progress(trace.quad_outcomes[i].fate), pb = progress(trace.quad_outcomes[b].fate);
    if (pi > pb || (pi == pb && centre_gap(i) < centre_gap(b))) best = static_cast<int>(i);
  }
  if (best >= 0) {
    const QuadOutcome& o = trace.quad_outcomes[static_cast<std::size_t>(best)];
    out.quad = best;
    if (pick) {
      out.stage = loss_stage_name(pick->stage);
      out.bits_wrong = pick->bits_wrong;
      out.text = tag + ": " + pick->text;
      return out;
    }
    using F = QuadOutcome::Fate;
    switch (o.fate) {
      case F::kBorderRejected:
        out.stage = "quad_rejected";
        out.text = "a candidate quad here was refused by the border pre-filter";
        break;
      case F::kNoHomography:
        out.stage = "quad_rejected";
        out.text = "a candidate quad here had degenerate corners (no homography)";
        break;
      case F::kUnreadable:
        out.stage = "quad_rejected";
        out.text = "a candidate quad here could not be read (cells outside the image or no border contrast)";
        break;
      case F::kNotDecoded:
        out.stage = "misread";
        out.text = "a candidate quad here was read, but no family decoded it within the bits corrected (" +
                   std::string(opt.hamming_by_family ? "by family, at most " : "") + std::to_string(opt.max_hamming) +
                   ") (give X,Y,FAMILY:ID to count the bits wrong)";
        break;
      case F::kTooFarForItsSource:
        out.stage = "misread";
        out.text = "a candidate quad here decoded as " + o.family + " id " + std::to_string(o.id) + " with " +
                   std::to_string(o.hamming) + " bits corrected, more than its source accepts (the line quads: " +
                   std::to_string(opt.line_quads.spare_bits) + " fewer than the family's)";
        break;
      case F::kDecoded:
        if (o.decision_margin < opt.min_decision_margin) {
          out.stage = "below_margin";
          out.text = "decoded as " + o.family + " id " + std::to_string(o.id) + ", decision margin " +
                     num(o.decision_margin) + " below the minimum " + num(opt.min_decision_margin);
        } else if (const auto& qc = trace.quads[static_cast<std::size_t>(best)].corners;
                   std::any_of(trace.withdrawn.begin(), trace.withdrawn.end(), [&](const Detection& w) {
                     // The withdrawn detection's corners are this quad's, re-ordered by its rotation.
                     return w.family == o.family && w.id == o.id &&
                            std::all_of(w.corners.begin(), w.corners.end(), [&](const Eigen::Vector2d& x) {
                              return std::find(qc.begin(), qc.end(), x) != qc.end();
                            });
                   })) {
          out.stage = "withdrawn";
          out.text = "decoded as " + o.family + " id " + std::to_string(o.id) +
                     ", then withdrawn by the occlusion refit: a side disagrees with the decoded tag (occluded or "
                     "bent) and could not be re-fitted from its visible part";
        } else {
          out.stage = "duplicate";
          out.text = "decoded as " + o.family + " id " + std::to_string(o.id) +
                     ", but a nearby detection of the same id, or of another id over the same quad, was kept "
                     "instead";
        }
        break;
    }
    if (hit) out.text += "; the detection here is " + hit->family + " id " + std::to_string(hit->id);
    return out;
  }
  if (hit) {  // a detection of another id holds the point, no candidate quad does (cannot happen, but say so)
    out.stage = "wrong_id";
    out.text = tag + ": detected as " + hit->family + " id " + std::to_string(hit->id);
    return out;
  }

  // 3. No quad holds the point: what is near it?
  double nearest_quad = std::numeric_limits<double>::infinity();
  for (const Quad& q : trace.quads)
    for (std::size_t k = 0; k < 4; ++k)
      nearest_quad = std::min(nearest_quad, point_to_segment(p.at, q.corners[k], q.corners[(k + 1) % 4]));
  std::size_t segments = 0;
  for (const Segment& s : trace.segments)
    if (point_to_segment(p.at, s.p0, s.p1) <= kExplainRadiusPx) ++segments;
  const std::string radius = num(kExplainRadiusPx) + " px";
  const std::string quad_note =
      std::isfinite(nearest_quad) ? " (the nearest candidate quad is " + num(nearest_quad) + " px away)" : "";
  if (opt.quad_finder == QuadFinderKind::kThreshold) {  // no clusters or segments to speak of
    out.stage = "no_quad";
    out.text = "no candidate quad holds the point: no outline of a dark square there in the adaptive threshold's "
               "classes" + threshold_near(p.at, trace, opt) + quad_note;
    return out;
  }
  if (segments > 0) {
    out.stage = "no_quad";
    out.text = std::to_string(segments) + " segments within " + radius + ", but no candidate quad holds the point" +
               quad_note;
    return out;
  }
  const double s = trace.segmentation_scale, off = (s - 1) / 2;
  std::size_t pixels = 0;
  for (const ClusterPixel& c : trace.clusters.pixels)
    if ((Eigen::Vector2d(s * c.x + off, s * c.y + off) - p.at).norm() <= kExplainRadiusPx) ++pixels;
  out.stage = pixels > 0 ? "no_segment" : "no_cluster";
  out.text = pixels > 0 ? std::to_string(pixels) + " gradient cluster pixels within " + radius + ", but no segment"
                        : "no gradient cluster within " + radius;
  out.text += quad_note;
  return out;
}

std::string explanation_json(const PointExplanation& e) {
  return "{\"at\": [" + json_number(e.at.x()) + ", " + json_number(e.at.y()) + "], \"given\": " + json_string(e.spec) +
         ", \"stage\": " + json_string(e.stage) +
         ", \"bits_wrong\": " + (e.bits_wrong >= 0 ? std::to_string(e.bits_wrong) : std::string("null")) +
         ", \"quad\": " + (e.quad >= 0 ? std::to_string(e.quad) : std::string("null")) +
         ", \"text\": " + json_string(e.text) + "}";
}

}  // namespace tagbench::cli::detect_cmd
