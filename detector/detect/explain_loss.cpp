#include "detect/explain_loss.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "codes/bits.hpp"

namespace tagbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double point_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// A fitted segment lies along the side a-b: parallel within 20 degrees, both ends within `tol` of
// the side's line, and covering at least 30 % of the side.
bool segment_along(const Segment& s, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tol) {
  const double len = (b - a).norm();
  if (!(len > 0) || !(s.length > 0)) return false;
  const Eigen::Vector2d dir = (b - a) / len, n(-dir.y(), dir.x());
  const Eigen::Vector2d sd = (s.p1 - s.p0) / s.length;
  if (std::abs(dir.x() * sd.y() - dir.y() * sd.x()) > std::sin(20.0 * M_PI / 180)) return false;
  if (std::abs(n.dot(s.p0 - a)) > tol || std::abs(n.dot(s.p1 - a)) > tol) return false;
  const double t0 = dir.dot(s.p0 - a), t1 = dir.dot(s.p1 - a);
  const double overlap = std::min(std::max(t0, t1), len) - std::max(std::min(t0, t1), 0.0);
  return overlap >= 0.3 * len;
}

std::string format(const char* fmt, double a, double b = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace

const char* loss_stage_name(LossStage s) {
  switch (s) {
    case LossStage::kNoCluster: return "no_cluster";
    case LossStage::kNoSegment: return "no_segment";
    case LossStage::kNoQuad: return "no_quad";
    case LossStage::kQuadRejected: return "quad_rejected";
    case LossStage::kMisread: return "misread";
    case LossStage::kWrongId: return "wrong_id";
    case LossStage::kDuplicate: return "duplicate";
    case LossStage::kBelowMargin: return "below_margin";
    case LossStage::kWithdrawn: return "withdrawn";
    case LossStage::kDetected: return "detected";
  }
  return "?";
}

double default_loss_tolerance(const Corners& c) {
  return std::max(2.0, 0.15 * perimeter(c) / 4);
}

LossExplanation explain_loss(const TagTruth& truth, const DetectorTrace& trace, std::span<const Detection> detections,
                             const DetectorOptions& options, double tolerance) {
  if (!truth.family) throw std::invalid_argument("explain_loss: no family given");
  const TagFamily& fam = *truth.family;
  if (truth.id < 0 || static_cast<std::size_t>(truth.id) >= fam.size())
    throw std::invalid_argument("explain_loss: id " + std::to_string(truth.id) + " is not in family " + fam.name());
  const double tol = tolerance > 0 ? tolerance : default_loss_tolerance(truth.corners);
  LossExplanation out;

  for (const Detection& d : detections)
    if (d.family == fam.name() && d.id == truth.id && max_corner_distance(d.corners, truth.corners) <= tol) {
      out.stage = LossStage::kDetected;
      out.text = "detected";
      return out;
    }

  // The most advanced outcome among the quads that match the tag's corners.
  const int d = fam.payload_width();
  const Code code = fam.codes()[static_cast<std::size_t>(truth.id)];
  double nearest = kInf;
  bool matched = false;
  for (std::size_t i = 0; i < trace.quads.size(); ++i) {
    for (int shift = 0; shift < 4; ++shift) {
      const double err = max_corner_distance(trace.quads[i].corners, truth.corners, shift);
      nearest = std::min(nearest, err);
      if (err > tol || i >= trace.quad_outcomes.size()) continue;
      const QuadOutcome& o = trace.quad_outcomes[i];
      LossExplanation e;
      using F = QuadOutcome::Fate;
      if (o.fate == F::kBorderRejected || o.fate == F::kNoHomography || o.fate == F::kUnreadable) {
        e.stage = LossStage::kQuadRejected;
        e.text = o.fate == F::kBorderRejected ? "a matching quad was refused by the border pre-filter"
                 : o.fate == F::kNoHomography ? "a matching quad had degenerate corners (no homography)"
                                              : "a matching quad could not be read (cells outside the image or no "
                                                "border contrast)";
      } else {
        // Quad corner `shift` is the printed top-left, so the tag's bits read through the quad are
        // rotate(code, d, shift) (decode_quads.hpp).
        const auto& bits = o.bits[static_cast<std::size_t>(d)];
        e.bits_wrong = bits ? hamming(*bits, rotate(code, d, shift)) : -1;
        if (o.fate == F::kNotDecoded) {
          e.stage = LossStage::kMisread;
          e.text = bits ? format("payload misread: %g bits wrong (%g corrected", e.bits_wrong,
                                        options.bits_corrected(fam.min_hamming())) + " for " + fam.name() + ")"
                        : "payload of the tag's width not read";
        } else if (o.fate == F::kTooFarForItsSource) {
          e.stage = LossStage::kMisread;
          e.text = format("payload misread: %g bits wrong, decoded as ", e.bits_wrong) + o.family + " id " +
                   std::to_string(o.id) + format(" with %g corrected, more than its quad's source accepts (the "
                                                 "line quads: %g fewer than the family's)",
                                                 o.hamming, options.line_quads.spare_bits);
        } else if (o.family != fam.name() || o.id != truth.id) {
          e.stage = LossStage::kWrongId;
          e.text = "decoded as " + o.family + " id " + std::to_string(o.id) +
                   (bits ? format(" (%g bits of the tag's code read wrong)", e.bits_wrong) : std::string());
        } else if (o.decision_margin < options.min_decision_margin) {
          e.stage = LossStage::kBelowMargin;
          e.text = format("decoded right, decision margin %.3g below the minimum %.3g", o.decision_margin,
                          options.min_decision_margin);
        } else if (std::any_of(trace.withdrawn.begin(), trace.withdrawn.end(), [&](const Detection& w) {
                     return w.family == fam.name() && w.id == truth.id &&
                            max_corner_distance(w.corners, truth.corners) <= tol;
                   })) {
          e.stage = LossStage::kWithdrawn;
          e.text = "decoded right, then withdrawn by the occlusion refit: a side disagrees with the decoded tag "
                   "(occluded or bent) and could not be re-fitted from its visible part";
        } else {
          e.stage = LossStage::kDuplicate;
          e.text = "decoded right, but a nearby detection of the same id, or of another id over the same quad, "
                   "was kept instead";
        }
      }
      if (!matched || e.stage > out.stage ||
          (e.stage == out.stage && e.bits_wrong >= 0 && (out.bits_wrong < 0 || e.bits_wrong < out.bits_wrong)))
        out = e;
      matched = true;
    }
  }
  if (matched) return out;

  // No matching quad: how far did the tag's border get?
  const Corners& c = truth.corners;
  int sides = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const auto a = c[k], b = c[(k + 1) % 4];
    if (std::any_of(trace.segments.begin(), trace.segments.end(), [&](const Segment& s) { return segment_along(s, a, b, tol); }))
      ++sides;
  }
  const std::string nearest_text =
      std::isfinite(nearest) ? format(" (the nearest quad is %.3g px off at its worst corner)", nearest) : "";
  // The threshold quad finder has no clusters or segments to speak of: its loss before a quad is no_quad.
  if (options.quad_finder != QuadFinderKind::kGradient) {
    out.stage = LossStage::kNoQuad;
    out.text = "no candidate quad matches the tag's corners" + nearest_text;
    return out;
  }
  out.sides_with_segment = sides;
  if (sides == 4) {
    out.stage = LossStage::kNoQuad;
    out.text = "segments on all 4 sides, but no candidate quad matches the tag's corners" + nearest_text;
    return out;
  }
  if (sides > 0) {
    out.stage = LossStage::kNoSegment;
    out.text = format("segments on %g of 4 sides", sides);
    return out;
  }
  // No segment at all: were there gradient pixels along the border?
  const double s = trace.segmentation_scale, off = (s - 1) / 2;
  std::size_t along = 0;
  for (const ClusterPixel& p : trace.clusters.pixels) {
    const Eigen::Vector2d q(s * p.x + off, s * p.y + off);
    for (std::size_t k = 0; k < 4; ++k)
      if (point_to_segment(q, c[k], c[(k + 1) % 4]) <= tol) {
        ++along;
        break;
      }
  }
  out.stage = along >= 4 ? LossStage::kNoSegment : LossStage::kNoCluster;
  out.text = along >= 4 ? "gradient clusters along the border, but no segment on any side"
                        : "no gradient cluster along the tag's border";
  return out;
}

}  // namespace tagbench
