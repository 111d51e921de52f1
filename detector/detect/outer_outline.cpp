#include "detect/outer_outline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "detect/homography.hpp"
#include "detect/payload_decode.hpp"
#include "detect/quad_fit.hpp"

namespace tagbench {

namespace {

// Each bin's envelope taken over the bin and its two neighbours (cyclic), `pick` of the three (max:
// the outermost point near the bin, min: the innermost): a bin that holds no point of the edge sought
// still sees the edge next to it.
template <class Pick>
void widen_cyclic(const std::vector<float>& envelope, std::vector<float>& widened, Pick pick) {
  const std::size_t nb = envelope.size();
  widened.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) widened[b] = pick(pick(envelope[(b + nb - 1) % nb], envelope[b]), envelope[(b + 1) % nb]);
}

}  // namespace

namespace {
// The bin by the formula itself (angle_bin's rare path: kept out of line so angle_bin inlines).
[[gnu::noinline, gnu::cold]] int angle_bin_exact(float dx, float dy, int bins, float per_radian) {
  const float a = std::atan2(dy, dx) + std::numbers::pi_v<float>;  // [0, 2 pi]
  return std::min(bins - 1, static_cast<int>(a * per_radian));
}
}  // namespace

int angle_bin(float dx, float dy, int bins, float per_radian) {
  const double ax = std::abs(static_cast<double>(dx)), ay = std::abs(static_cast<double>(dy));
  // Also every NaN and infinity: ax and ay are then not both in (0, 1e30).
  if (!(ax > 0 && ay > 0 && ax < 1e30 && ay < 1e30)) return angle_bin_exact(dx, dy, bins, per_radian);
  // atan on [0, 1] within 2e-8 rad (Abramowitz and Stegun 4.4.49), then the quadrant. The float
  // sum and product of the exact bin add under 3e-7 rad and half a float ulp of the bin number (under
  // 3e-5 of a bin at 1024 bins); a value within 1e-3 of a bin's edge is left to the exact formula, so
  // the bin is always the same.
  const bool steep = ay > ax;
  const double z = steep ? ax / ay : ay / ax, z2 = z * z;
  double p = z * (1 + z2 * (-0.3333314528 + z2 * (0.1999355085 + z2 * (-0.1420889944 + z2 * (0.1065626393 +
                 z2 * (-0.0752896400 + z2 * (0.0429096138 + z2 * (-0.0161657367 + z2 * 0.0028662257))))))));
  if (steep) p = 0.5 * std::numbers::pi - p;
  if (dx < 0) p = std::numbers::pi - p;
  if (dy < 0) p = -p;
  const double t = (p + static_cast<double>(std::numbers::pi_v<float>)) * static_cast<double>(per_radian);
  constexpr double kMargin = 1e-3;
  const double lo = t - kMargin, hi = t + kMargin;  // truncation is the floor from here: lo >= 0
  if (!(lo >= 0) || static_cast<int>(lo) != static_cast<int>(hi)) return angle_bin_exact(dx, dy, bins, per_radian);
  return std::min(bins - 1, static_cast<int>(lo));
}

void outer_outline_points(std::span<const BoundaryPoint> group, const OuterOutlineOptions& opt,
                          OuterOutlineScratch& s, std::vector<BoundaryPoint>& out, std::size_t min_points) {
  out.clear();
  s.radius.clear();  // inner_outline_points: nothing to take from a call that kept nothing
  one_side_points(group, true, s.side);
  if (s.side.empty() || s.side.size() < min_points) return;
  const auto [xmin, xmax, ymin, ymax] = bounding_box(s.side);
  // Doubled coordinates throughout: the ratio test does not care about the scale.
  const float cx = 0.5f * static_cast<float>(xmin + xmax), cy = 0.5f * static_cast<float>(ymin + ymax);
  const int nb = std::clamp(opt.bins, 8, 1024);
  const float per_radian = static_cast<float>(nb) / (2 * std::numbers::pi_v<float>);
  const std::size_t n = s.side.size();
  s.radius.resize(n);
  s.bin.resize(n);
  s.envelope.assign(static_cast<std::size_t>(nb), 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const float dx = static_cast<float>(s.side[i].x2) - cx, dy = static_cast<float>(s.side[i].y2) - cy;
    const int b = angle_bin(dx, dy, nb, per_radian);
    s.radius[i] = std::sqrt(dx * dx + dy * dy);
    s.bin[i] = b;
    float& e = s.envelope[static_cast<std::size_t>(b)];
    e = std::max(e, s.radius[i]);
  }
  widen_cyclic(s.envelope, s.widened, [](float a, float b) { return std::max(a, b); });
  const float keep = static_cast<float>(1 - opt.tolerance);
  for (std::size_t i = 0; i < n; ++i)
    if (s.radius[i] >= keep * s.widened[static_cast<std::size_t>(s.bin[i])]) out.push_back(s.side[i]);
}

std::size_t inner_outline_points(const OuterOutlineOptions& opt, OuterOutlineScratch& s, std::vector<BoundaryPoint>& out) {
  out.clear();
  const std::size_t n = s.radius.size(), nb = s.envelope.size();
  if (n == 0 || nb == 0) return 0;
  s.inner_envelope.assign(nb, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    float& e = s.inner_envelope[static_cast<std::size_t>(s.bin[i])];
    e = std::min(e, s.radius[i]);
  }
  const auto covered = static_cast<std::size_t>(
      std::count_if(s.inner_envelope.begin(), s.inner_envelope.end(), [](float e) { return std::isfinite(e); }));
  if (static_cast<double>(covered) < opt.innermost_min_coverage * static_cast<double>(nb)) return 0;
  widen_cyclic(s.inner_envelope, s.inner_widened, [](float a, float b) { return std::min(a, b); });
  const auto keep_in = static_cast<float>(1 + opt.tolerance), keep_out = static_cast<float>(1 - opt.tolerance);
  std::size_t also_outer = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = static_cast<std::size_t>(s.bin[i]);
    if (s.radius[i] > keep_in * s.inner_widened[b]) continue;
    out.push_back(s.side[i]);
    also_outer += s.radius[i] >= keep_out * s.widened[b];
  }
  return also_outer;
}

namespace {

// Bilinear sample (payload_decode.hpp's), the point clamped into the image first.
float sample(const ImageF& img, const Eigen::Vector2d& p) {
  return sample_bilinear_inside(img, {std::clamp(p.x(), 0.0, static_cast<double>(img.width - 1)),
                                      std::clamp(p.y(), 0.0, static_cast<double>(img.height - 1))});
}

}  // namespace

bool outline_has_ring(const Corners& q, const ImageF& img, const OuterOutlineOptions& opt) {
  if (img.empty()) return false;
  // (u, v) in [0, 1]^2 -> image: q[0] at (0, 0), q[1] at (1, 0), q[2] at (1, 1), q[3] at (0, 1).
  auto at = [&](double u, double v) {
    return (1 - u) * (1 - v) * q[0] + u * (1 - v) * q[1] + u * v * q[2] + (1 - u) * v * q[3];
  };
  constexpr double kIn = 1.0 / 16, kOut = -1.0 / 16;
  double sum = 0;
  bool every_side = true;
  int slack_sides = 0;  // sides that pass only with the slack
  for (int side = 0; side < 4; ++side) {
    int up = 0, up_plain = 0;
    for (const double t : {0.2, 0.4, 0.6, 0.8}) {
      // side 0: v = 0 (q0 -> q1), 1: u = 1, 2: v = 1, 3: u = 0; d is the depth into the square.
      auto uv = [&](double d) -> Eigen::Vector2d {
        switch (side) {
          case 0: return at(t, d);
          case 1: return at(1 - d, t);
          case 2: return at(t, 1 - d);
          default: return at(d, t);
        }
      };
      float step = sample(img, uv(kOut)) - sample(img, uv(kIn));
      up_plain += step > 0;
      // The pair moved outward too: the outline is the threshold's, which a blurred 1-cell border
      // with light payload cells behind it can leave a pixel or two inside the square's edge.
      if (opt.ring_outward_slack > 0)
        step = std::max(step, sample(img, uv(kOut - opt.ring_outward_slack)) - sample(img, uv(kIn - opt.ring_outward_slack)));
      up += step > 0;
      sum += step;
    }
    every_side = every_side && up >= opt.ring_min_share * 4;
    slack_sides += up_plain < opt.ring_min_share * 4;
  }
  if (!every_side || slack_sides > opt.ring_slack_sides || sum / 16 < opt.ring_min_step) return false;
  // The shape: the shortest side at least min_side_ratio of the longest (a square tilted 65 degrees
  // away keeps about 0.4); the slivers an outline of texture gives fail here.
  const auto [shortest, longest] = side_length_range(q);
  return shortest >= opt.min_side_ratio * longest;
}

}  // namespace tagbench
