#include "detect/bent_decode.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <Eigen/Dense>

#include "detect/detector.hpp"
#include "detect/decode_quads.hpp"
#include "detect/homography.hpp"

namespace tagbench {
namespace {

// Intersection of the lines through p0, p1 and q0, q1; nullopt when parallel.
std::optional<Eigen::Vector2d> intersect(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1,
                                         const Eigen::Vector2d& q0, const Eigen::Vector2d& q1) {
  const Eigen::Vector2d a = p1 - p0, b = q1 - q0, d = q0 - p0;
  const double den = a.x() * b.y() - a.y() * b.x();
  if (!(std::abs(den) > 1e-9)) return std::nullopt;
  return p0 + (d.x() * b.y() - d.y() * b.x()) / den * a;
}

// The homography of a half: its image corners (in the tag square's corner order) for the tag
// rectangle [u0,u1] x [v0,v1], composed so that it takes tag coordinates.
std::optional<Eigen::Matrix3d> half_homography(const Corners& c, double u0, double u1, double v0, double v1) {
  const auto H = tag_homography(c);
  if (!H) return std::nullopt;
  Eigen::Matrix3d A;  // [u0,u1] x [v0,v1] -> [-1,1]^2
  A << 2 / (u1 - u0), 0, -(u1 + u0) / (u1 - u0), 0, 2 / (v1 - v0), -(v1 + v0) / (v1 - v0), 0, 0, 1;
  return *H * A;
}

struct Fold {
  Corners corners;             // the quad's corners on the broken lines
  Eigen::Matrix3d first, second;  // homographies of the halves u < 0 and u > 0 (or v < 0, v > 0)
  bool across_u;               // the fold is the line u = 0 (bent sides 0 and 2), else v = 0
};

// The folded geometry from the measured sides, for the fold across sides `pair` and `pair + 2`.
std::optional<Fold> fold_geometry(const std::array<SideKink, 4>& s, std::size_t pair) {
  Corners c;
  for (std::size_t i = 0; i < 4; ++i) {  // corner i: side i-1's last piece meets side i's first piece
    const SideKink& prev = s[(i + 3) % 4];
    const SideKink& next = s[i];
    const auto p = intersect(prev.fold_point, prev.ends[1], next.ends[0], next.fold_point);
    if (!p) return std::nullopt;
    c[i] = *p;
  }
  Fold f;
  f.corners = c;
  f.across_u = pair == 0;
  std::optional<Eigen::Matrix3d> a, b;
  if (f.across_u) {  // fold points on side 0 (top, corner 0 -> 1) and side 2 (bottom, corner 2 -> 3)
    const Eigen::Vector2d ft = s[0].fold_point, fb = s[2].fold_point;
    a = half_homography({c[0], ft, fb, c[3]}, -1, 0, -1, 1);
    b = half_homography({ft, c[1], c[2], fb}, 0, 1, -1, 1);
  } else {  // fold points on side 1 (right, corner 1 -> 2) and side 3 (left, corner 3 -> 0)
    const Eigen::Vector2d fr = s[1].fold_point, fl = s[3].fold_point;
    a = half_homography({c[0], c[1], fr, fl}, -1, 1, -1, 0);
    b = half_homography({fl, fr, c[2], c[3]}, -1, 1, 0, 1);
  }
  if (!a || !b) return std::nullopt;
  f.first = *a, f.second = *b;
  return f;
}

}  // namespace

std::vector<Detection> decode_bent_quads(const ImageF& gray, const ImageF& decode_image, std::span<const Quad> quads,
                                         std::span<QuadOutcome> outcomes, std::span<const TagFamily> families,
                                         int max_hamming, bool hamming_by_family, const PayloadAreaOptions& area,
                                         double min_contrast, const BentReadOptions& opt) {
  std::vector<Detection> found;
  if (!opt.enabled || outcomes.size() != quads.size() || families.empty()) return found;
  PayloadAreaOptions area_opt = area;
  area_opt.min_contrast = min_contrast;
  const int max_d = max_payload_width(families);
  for (std::size_t qi = 0; qi < quads.size(); ++qi) {
    QuadOutcome& outcome = outcomes[qi];
    if (outcome.fate != QuadOutcome::Fate::kNotDecoded) continue;
    if (!(side_length_range(quads[qi].corners).first >= opt.min_side_px)) continue;
    BorderKinkOptions k = opt.kink;
    k.cells_across = max_d + 2;
    BorderKinkOptions quick = k;
    quick.samples = opt.precheck_samples;
    quick.max_fold_offset = 0;
    const auto first_look = measure_border_kinks(gray, quads[qi].corners, quick);
    if (!first_look || !(max_kink_px(*first_look) >= opt.precheck_fraction * opt.min_kink_px)) continue;
    const auto sides = measure_border_kinks(gray, quads[qi].corners, k);
    if (!sides) continue;
    if (!std::all_of(sides->begin(), sides->end(), [](const SideKink& s) { return s.valid; })) continue;
    // The pair whose more bent side bends more is the folded one.
    const auto strength = [&](std::size_t i) { return std::max(std::abs((*sides)[i].kink_px), std::abs((*sides)[i + 2].kink_px)); };
    const std::size_t pair = strength(0) >= strength(1) ? 0 : 1;
    if (!(strength(pair) >= opt.min_kink_px)) continue;
    {
      const auto fold = fold_geometry(*sides, pair);
      if (!fold) continue;
      const TagToImage map = [&](const Eigen::Vector2d& u) {
        const bool first = fold->across_u ? u.x() < 0 : u.y() < 0;
        return apply_homography(first ? fold->first : fold->second, u);
      };
      std::array<std::optional<PayloadReading>, kMaxPayloadWidth + 1> by_width;
      std::array<bool, kMaxPayloadWidth + 1> read{};
      for (const TagFamily& f : families) {
        const auto d = static_cast<std::size_t>(f.payload_width());
        if (!read[d]) by_width[d] = read_payload_area(decode_image, map, static_cast<int>(d), area_opt);
        read[d] = true;
      }
      Detection best;
      if (!decode_readings(families, by_width, max_hamming, hamming_by_family, best)) continue;
      best.corners = printed_corners(fold->corners, best.rotation);
      const auto H = tag_homography(best.corners);
      if (!H) continue;
      best.homography = *H;
      best.center = apply_homography(*H, Eigen::Vector2d::Zero());
      best.observed_perimeter = quads[qi].observed_perimeter;
      mark_decoded(outcome, best);
      found.push_back(std::move(best));
    }
  }
  return found;
}

}  // namespace tagbench
