// The realistic set's ground and light (realistic_parts.hpp). The ground is meant to give a detector
// what an outdoor photograph gives it: many strong straight edges and corners that make quads, dark
// squares with light marks inside (windows, labels, other markers), text, and texture at every scale.
#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "realistic/realistic_parts.hpp"

namespace tagbench::bench::realistic_parts {

namespace {

// Band-limited noise: normal draws on a grid of gw x gh cells, resized (bicubic) to `size`.
cv::Mat smooth_noise(int gw, int gh, cv::Size size, Draws& draws) {
  cv::Mat g(std::max(gh, 2), std::max(gw, 2), CV_32F);
  cv::RNG rng(draws.next());
  rng.fill(g, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat out;
  cv::resize(g, out, size, 0, 0, cv::INTER_CUBIC);
  return out;
}

// A rectangle of w x h output pixels centred at c (supersampled coordinates), turned by angle a.
std::vector<cv::Point> rotated_rect(cv::Point2d c, double w, double h, double a, double ss) {
  const double ca = std::cos(a), sa = std::sin(a);
  std::vector<cv::Point> p;
  for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const double x = sx * w / 2 * ss, y = sy * h / 2 * ss;
    p.emplace_back(static_cast<int>(std::lround(c.x + ca * x - sa * y)), static_cast<int>(std::lround(c.y + sa * x + ca * y)));
  }
  return p;
}

}  // namespace

std::uint64_t frame_seed(std::uint64_t seed, int index) {
  Draws d{seed ^ (static_cast<std::uint64_t>(index) * 0x9e3779b97f4a7c15ULL + 0x2545f4914f6cdd1dULL)};
  d.next();
  return d.next();
}

cv::Mat make_ground(int width, int height, int ss, Draws& dr) {
  const cv::Size big(width * ss, height * ss);
  const double s = ss;
  // Texture at three scales: patches of ground, gravel, grain.
  const double base = dr.uniform(0.25, 0.6);
  cv::Mat g = smooth_noise(width / 64, height / 64, big, dr) * dr.uniform(0.05, 0.15) + base;
  g += smooth_noise(width / 3, height / 3, big, dr) * dr.uniform(0.02, 0.08);
  g += smooth_noise(width, height, big, dr) * dr.uniform(0.01, 0.05);
  const auto P = [&] { return cv::Point2d(dr.uniform(0, big.width), dr.uniform(0, big.height)); };
  const auto gray = [&] { return cv::Scalar(dr.uniform(0.05, 0.9)); };
  const auto thick = [&](double lo, double hi) { return std::max(1, static_cast<int>(std::lround(dr.uniform(lo, hi) * s))); };
  // Paving: rotated grids of joints (corners by the hundred).
  for (int k = 0, n = dr.below(3); k < n; ++k) {
    const cv::Point2d c = P();
    const double a = dr.uniform(0, M_PI), step = dr.uniform(12, 45) * s, extent = dr.uniform(80, 250) * s;
    const double ca = std::cos(a), sa = std::sin(a);
    const cv::Scalar v = gray();
    const int t = thick(0.7, 2.5);
    for (double o = -extent; o <= extent; o += step) {
      cv::line(g, cv::Point2d(c.x + ca * o - sa * extent, c.y + sa * o + ca * extent),
               cv::Point2d(c.x + ca * o + sa * extent, c.y + sa * o - ca * extent), v, t);
      cv::line(g, cv::Point2d(c.x - sa * o - ca * extent, c.y + ca * o - sa * extent),
               cv::Point2d(c.x - sa * o + ca * extent, c.y + ca * o + sa * extent), v, t);
    }
  }
  // Filled and outlined rectangles of every size (boxes, boards, labels).
  for (int k = 0, n = 20 + dr.below(30); k < n; ++k) {
    const double w = std::exp(dr.uniform(std::log(6.0), std::log(160.0))), h = w * dr.uniform(0.3, 2.0);
    const auto poly = rotated_rect(P(), w, h, dr.uniform(0, M_PI), s);
    if (dr.chance(0.7)) cv::fillConvexPoly(g, poly, gray());
    else cv::polylines(g, poly, true, gray(), thick(1, 4));
  }
  // Straight edges and lines (kerbs, sticks, cables).
  for (int k = 0, n = 8 + dr.below(20); k < n; ++k) cv::line(g, P(), P(), gray(), thick(0.8, 5));
  // Blobs (stones, leaves).
  for (int k = 0, n = 10 + dr.below(30); k < n; ++k)
    cv::circle(g, P(), static_cast<int>(dr.uniform(2, 25) * s), gray(), cv::FILLED);
  // Text-like marks.
  static const std::string kChars = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-/";
  for (int k = 0, n = 6 + dr.below(20); k < n; ++k) {
    std::string text;
    for (int c = 0, len = 2 + dr.below(9); c < len; ++c) text += kChars[static_cast<std::size_t>(dr.below(static_cast<int>(kChars.size())))];
    const double height_px = dr.uniform(5, 28);  // cap height in output pixels; Hershey simplex caps are ~22 units at scale 1
    cv::putText(g, text, P(), cv::FONT_HERSHEY_SIMPLEX, height_px * s / 22.0, gray(),
                std::max(1, static_cast<int>(std::lround(height_px * s / dr.uniform(6, 12)))));
  }
  // Tag-like decoys: dark squares with a light random pattern inside (false quad candidates that even
  // decode-like patterns cannot tell apart before the code check).
  for (int k = 0, n = 2 + dr.below(8); k < n; ++k) {
    const cv::Point2d c = P();
    const double side = dr.uniform(10, 45), a = dr.uniform(0, M_PI);
    const double dark = dr.uniform(0.03, 0.2), light = dr.uniform(0.5, 0.9);
    cv::fillConvexPoly(g, rotated_rect(c, side * 1.5, side * 1.5, a, s), cv::Scalar(light));
    cv::fillConvexPoly(g, rotated_rect(c, side, side, a, s), cv::Scalar(dark));
    const int cells = 3 + dr.below(4);
    const double cell = side / (cells + 2), ca = std::cos(a), sa = std::sin(a);
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x) {
        if (!dr.chance(0.5)) continue;
        const double ox = (x - (cells - 1) / 2.0) * cell * s, oy = (y - (cells - 1) / 2.0) * cell * s;
        cv::fillConvexPoly(g, rotated_rect({c.x + ca * ox - sa * oy, c.y + sa * ox + ca * oy}, cell, cell, a, s), cv::Scalar(light));
      }
  }
  cv::max(g, 0.01, g);
  cv::min(g, 0.98, g);
  return g;
}

cv::Mat make_light(int width, int height, double unevenness, double shadow_probability, Draws& dr, bool& shadow) {
  // A linear fall-off in a random direction plus a broad bump: sun and sky, a building's reflection.
  const double a = dr.uniform(0, 2 * M_PI), ca = std::cos(a), sa = std::sin(a), diag = std::hypot(width, height);
  const double bx = dr.uniform(0, width), by = dr.uniform(0, height), br = dr.uniform(0.2, 0.6) * diag;
  const double slope = dr.uniform(0.3, 1.0), bump = dr.uniform(0, 1);
  cv::Mat light(height, width, CV_32F);
  for (int y = 0; y < height; ++y) {
    float* row = light.ptr<float>(y);
    for (int x = 0; x < width; ++x) {
      const double lin = 0.5 + ((x - width / 2.0) * ca + (y - height / 2.0) * sa) / diag;  // 0..1 across
      const double b = std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / (2 * br * br));
      const double v = (1 - slope * lin) * (1 - bump) + b * bump;  // 0..1, brightest 1
      row[x] = static_cast<float>(1 - unevenness + unevenness * v);
    }
  }
  shadow = dr.chance(shadow_probability);
  if (shadow) {
    // A polygon of shade with a straight-sided penumbra (a wall's or a cube's shadow).
    cv::Mat mask(height, width, CV_32F, cv::Scalar(1.0));
    std::vector<cv::Point> poly;
    const cv::Point2d c(dr.uniform(0, width), dr.uniform(0, height));
    const double r = dr.uniform(0.2, 0.6) * diag, a0 = dr.uniform(0, 2 * M_PI);
    for (int k = 0; k < 5; ++k) {
      const double ak = a0 + k * 2 * M_PI / 5 + dr.uniform(-0.4, 0.4), rk = r * dr.uniform(0.5, 1.0);
      poly.emplace_back(static_cast<int>(c.x + rk * std::cos(ak)), static_cast<int>(c.y + rk * std::sin(ak)));
    }
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(dr.uniform(0.35, 0.6)));
    cv::GaussianBlur(mask, mask, cv::Size(0, 0), dr.uniform(0.8, 3.0));
    light = light.mul(mask);
  }
  return light;
}

}  // namespace tagbench::bench::realistic_parts
