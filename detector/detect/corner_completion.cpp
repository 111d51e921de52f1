#include "detect/corner_completion.hpp"

#include "detect/detector.hpp"  // QuadOutcome
#include "detect/homography.hpp"
#include "detect/line_quads.hpp"  // centre_covered
#include "detect/payload_decode.hpp"  // sample_bilinear

namespace tagbench {

Corners complete_corner(const Corners& q, int k) {
  Corners c = q;
  const auto at = [&](int i) { return q[static_cast<std::size_t>((k + i) & 3)]; };
  c[static_cast<std::size_t>(k & 3)] = at(1) + at(3) - at(2);
  return c;
}

namespace {

// Every turn of q the way `sign` says (+1: clockwise on screen, y down; -1: counter-clockwise).
bool convex_turning(const Corners& q, double sign) {
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d d1 = q[(i + 1) & 3] - q[i], d2 = q[(i + 2) & 3] - q[(i + 1) & 3];
    if (!(sign * (d1.x() * d2.y() - d1.y() * d2.x()) > 0)) return false;
  }
  return true;
}

}  // namespace

bool completion_supported(const ImageF& img, int d, const Corners& c, int k, const CornerCompletionOptions& opt) {
  if (opt.support_samples < 1 || img.width < 2 || img.height < 2) return false;
  const Eigen::Vector2d centre = 0.25 * (c[0] + c[1] + c[2] + c[3]);
  const Eigen::Vector2d corner = c[static_cast<std::size_t>(k & 3)];
  // Half a ring cell: the black square is d + 2 cells across.
  const double half_cell = 0.5 * 0.25 * perimeter(c) / (d + 2);
  int good = 0;
  for (const int nb : {(k + 1) & 3, (k + 3) & 3}) {
    const Eigen::Vector2d other = c[static_cast<std::size_t>(nb)];
    Eigen::Vector2d n(-(corner - other).y(), (corner - other).x());
    if (!(n.norm() > 0)) return false;
    n.normalize();
    if (n.dot(0.5 * (corner + other) - centre) < 0) n = -n;  // outward
    for (int i = 0; i < opt.support_samples; ++i) {
      // The half of the side next to the corner, ends left out.
      const double t = 0.5 * (i + 0.5) / opt.support_samples;
      const Eigen::Vector2d p = corner + t * (other - corner);
      const Eigen::Vector2d in = p - half_cell * n, out = p + half_cell * n;
      const auto light = sample_bilinear(img, out), dark = sample_bilinear(img, in);
      if (light && dark && *light - *dark >= opt.min_contrast) ++good;
    }
  }
  return good >= opt.min_support * 2 * opt.support_samples;
}

std::vector<Quad> completed_quads(const ImageF& img, int d, std::span<const Quad> quads,
                                  std::span<const QuadOutcome> outcomes, std::span<const Corners> covered,
                                  const CornerCompletionOptions& opt) {
  std::vector<Quad> out;
  if (!opt.enabled || quads.size() != outcomes.size()) return out;
  for (std::size_t i = 0; i < quads.size(); ++i) {
    const QuadOutcome::Fate fate = outcomes[i].fate;
    if (fate != QuadOutcome::Fate::kNotDecoded && !(opt.border_rejected && fate == QuadOutcome::Fate::kBorderRejected))
      continue;
    const Corners& q = quads[i].corners;
    const auto [shortest, longest] = side_length_range(q);
    if (!(shortest >= opt.min_side_px) || !(longest <= opt.max_side_px)) continue;
    if (centre_covered(quads[i], covered)) continue;
    // The completion must turn the way the quad does (its winding, from its area).
    const double winding = twice_signed_area(q) > 0 ? 1.0 : -1.0;
    for (int k = 0; k < 4; ++k) {
      const Corners c = complete_corner(q, k);
      if (!((c[static_cast<std::size_t>(k)] - q[static_cast<std::size_t>(k)]).norm() >= opt.min_move_px)) continue;
      if (!convex_turning(c, winding) || !completion_supported(img, d, c, k, opt)) continue;
      Quad n;
      n.corners = c;
      n.segments = {-1, -1, -1, -1};
      n.observed_perimeter = 0;
      out.push_back(n);
    }
  }
  return out;
}

}  // namespace tagbench
