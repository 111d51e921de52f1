#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/blur.hpp"
#include "detect/border_kink.hpp"
#include "detect/homography.hpp"
#include "detect/payload_decode.hpp"
#include "synthetic_folded.hpp"
#include "synthetic_tag.hpp"

namespace test_border_kink {

using namespace tagbench;

// A flat tag's sides are straight: every kink is a small fraction of a pixel, the blur about the
// rendering's (an 8x8-supersampled box, then a Gaussian of 0.6 px).
TEST(BorderKink, FlatTagSidesAreStraight) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = synth::square_tag_corners(60.3, 58.7, 64, 0.3);
  const ImageF img = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, 5), synth::homography_for(c)), 0.6);
  const auto s = measure_border_kinks(img, c);
  ASSERT_TRUE(s.has_value());
  for (const SideKink& k : *s) {
    EXPECT_TRUE(k.valid);
    EXPECT_LT(std::abs(k.kink_px), 0.15);
  }
  EXPECT_LT(max_kink_px(*s), 0.15);
  EXPECT_NEAR(median_blur_px(*s), 0.65, 0.2);
}

// A heavier blur is measured as such (sigma 2 px on top of the rendering's own).
TEST(BorderKink, BlurIsMeasured) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = synth::square_tag_corners(60, 60, 64, 0.1);
  const ImageF img = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, 9), synth::homography_for(c)), 2.0);
  const auto s = measure_border_kinks(img, c);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(median_blur_px(*s), 2.0, 0.3);
}

// A tag folded along its vertical centre line, the fold points 2 px outside the straight sides: the
// top and bottom sides show the kink (2 px from the chord of their ends) at their middles, the left
// and right sides stay straight; the fold points are found within a few tenths of a pixel.
TEST(BorderKink, FoldedTagShowsItsKinkAndFold) {
  const TagFamily& f = builtin_family("36h11");
  const synth::FoldedTag t = synth::folded_square(60.4, 60.2, 64, 2.0, 2.0);
  const ImageF img = gaussian_blur(synth::render_folded(120, 120, tag_cells(f, 3), t), 0.6);
  // The quad a line fit would give: straight sides through the bent ones' average (here: the ends).
  const auto s = measure_border_kinks(img, t.corners);
  ASSERT_TRUE(s.has_value());
  for (const SideKink& k : *s) ASSERT_TRUE(k.valid);
  EXPECT_NEAR(std::abs((*s)[0].kink_px), 2.0, 0.3);
  EXPECT_NEAR(std::abs((*s)[2].kink_px), 2.0, 0.3);
  EXPECT_LT(std::abs((*s)[1].kink_px), 0.2);
  EXPECT_LT(std::abs((*s)[3].kink_px), 0.2);
  EXPECT_LT(((*s)[0].fold_point - t.fold_top).norm(), 0.4);
  EXPECT_LT(((*s)[2].fold_point - t.fold_bottom).norm(), 0.4);
  EXPECT_GT(max_kink_significance(*s), 10);
}

// Corners that give no homography, or an empty image: no measurement.
TEST(BorderKink, DegenerateInputGivesNothing) {
  const ImageF img(40, 40);
  const Corners line = {Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 3), Eigen::Vector2d(4, 4)};
  EXPECT_FALSE(measure_border_kinks(img, line).has_value());
  EXPECT_FALSE(measure_border_kinks(ImageF(), synth::square_tag_corners(20, 20, 10, 0)).has_value());
}

namespace {

// measure_border_kinks written out plainly (every sample taken, each checked against the image): the
// reference its scans (samples reused along the scan, 2 x 2 cells kept, the ends' inside test) must
// match bit for bit.
std::optional<std::array<SideKink, 4>> reference_kinks(const ImageF& img, const Corners& corners, const BorderKinkOptions& opt) {
  const auto H = tag_homography(corners);
  if (!H) return std::nullopt;
  const Corners& tag = tag_square_corners();
  const Eigen::Vector2d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  const double h = opt.derivative_half_px;
  struct Scan {
    double offset, sigma;
  };
  const auto scan = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& n, double c, double range) -> std::optional<Scan> {
    double sw = 0, st = 0, stt = 0;
    bool any = false;
    for (double t = c - range; t <= c + range + 1e-9; t += opt.step_px) {
      any = true;
      const auto hi = sample_bilinear(img, p + (t + h) * n), lo = sample_bilinear(img, p + (t - h) * n);
      if (!hi || !lo) return std::nullopt;
      const double g = *hi - *lo;
      if (g <= 0) continue;
      sw += g * g, st += g * g * t, stt += g * g * t * t;
    }
    if (!any || !(sw > 0)) return std::nullopt;
    const double mean = st / sw, var = std::max(0.0, stt / sw - mean * mean);
    return Scan{mean, std::sqrt(std::max(0.0, 2 * var - h * h / 3))};
  };
  std::array<SideKink, 4> out;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % 4];
    const double len = (b - a).norm();
    if (!(len > 1e-6)) continue;
    Eigen::Vector2d n((b - a).y() / len, -(b - a).x() / len);
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    const double range = std::max(opt.min_range_px, opt.range_cells * len / opt.cells_across);
    const auto on_side = [&](double s) { return apply_homography(*H, tag[i] + 0.5 * (s + 1) * (tag[(i + 1) % 4] - tag[i])); };
    std::vector<Eigen::Vector2d> pts;
    std::vector<double> blur;
    for (int k = 0; k < opt.samples; ++k) {
      const double s = -1 + opt.end_margin + (2 - 2 * opt.end_margin) * (k + 0.5) / opt.samples;
      const Eigen::Vector2d p = on_side(s);
      auto e = scan(p, n, 0, range);
      if (e) e = scan(p, n, e->offset, range);
      if (!e) continue;
      pts.emplace_back(s, e->offset);
      blur.push_back(e->sigma);
    }
    if (2 * static_cast<int>(pts.size()) < opt.samples) continue;
    const auto best = fit_broken_line(pts, opt.max_fold_offset);  // tested alone below
    if (!best) continue;
    SideKink& k = out[i];
    k.valid = true;
    k.kink_px = best->c;
    k.fold_s = best->s0;
    k.rms_px = std::sqrt(best->ssr / static_cast<double>(pts.size()));
    k.kink_se_px = std::sqrt(best->ssr / std::max(1.0, static_cast<double>(pts.size()) - 3) * std::max(0.0, best->c_var));
    const auto o = [&](double s) { return best->a + best->b * s + best->c * std::abs(s - best->s0); };
    k.fold_point = on_side(best->s0) + o(best->s0) * n;
    k.ends = {on_side(-1) + o(-1) * n, on_side(1) + o(1) * n};
    std::nth_element(blur.begin(), blur.begin() + static_cast<std::ptrdiff_t>(blur.size() / 2), blur.end());
    k.blur_px = blur[blur.size() / 2];
  }
  return out;
}

}  // namespace

// Random tags (some reaching past the image's edge, where scans are refused), blurs and scan
// settings (steps whose offsets add exactly and ones that do not, so samples are reused or not):
// every field of every side equals the plain reference's, bit for bit.
TEST(BorderKink, ScansMatchThePlainReferenceBitForBit) {
  const TagFamily& f = builtin_family("36h11");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(10, 110), size(12, 90), angle(-3.2, 3.2), blur(0.4, 2.5);
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Corners c = synth::square_tag_corners(pos(rng), pos(rng), size(rng), angle(rng));
    const ImageF img = gaussian_blur(synth::render_tag(120, 120, tag_cells(f, trial), synth::homography_for(c)), blur(rng));
    BorderKinkOptions opt;
    opt.step_px = trial % 3 == 0 ? 0.25 : trial % 3 == 1 ? 0.3 : 0.1;
    opt.derivative_half_px = trial % 2 ? 0.5 : 0.35;
    opt.max_fold_offset = trial % 4 ? 0.5 : 0;
    const auto got = measure_border_kinks(img, c, opt);
    const auto want = reference_kinks(img, c, opt);
    ASSERT_EQ(got.has_value(), want.has_value()) << trial;
    if (!got) continue;
    for (std::size_t i = 0; i < 4; ++i) {
      const SideKink &g = (*got)[i], &w = (*want)[i];
      ASSERT_EQ(g.valid, w.valid) << trial << " side " << i;
      if (!g.valid) continue;
      ++compared;
      EXPECT_EQ(g.kink_px, w.kink_px) << trial << " side " << i;
      EXPECT_EQ(g.fold_s, w.fold_s);
      EXPECT_EQ(g.rms_px, w.rms_px);
      EXPECT_EQ(g.kink_se_px, w.kink_se_px);
      EXPECT_EQ(g.blur_px, w.blur_px);
      EXPECT_EQ(g.fold_point, w.fold_point);
      EXPECT_EQ(g.ends[0], w.ends[0]);
      EXPECT_EQ(g.ends[1], w.ends[1]);
    }
  }
  EXPECT_GT(compared, 60);  // most sides measured (some tags reach past the image)
}

// The broken line alone: exact points of o(s) = a + b s + c |s - s0| with s0 on the grid give the
// line back with no residual; with no kink the fit says c = 0.
TEST(BorderKink, BrokenLineFitRecoversAKnownFold) {
  std::vector<Eigen::Vector2d> pts;
  for (int k = 0; k <= 20; ++k) {
    const double s = -1 + 0.1 * k;
    pts.emplace_back(s, 0.3 - 0.2 * s + 0.8 * std::abs(s - 0.25));
  }
  const auto f = fit_broken_line(pts, 0.5);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->a, 0.3, 1e-9);
  EXPECT_NEAR(f->b, -0.2, 1e-9);
  EXPECT_NEAR(f->c, 0.8, 1e-9);
  EXPECT_NEAR(f->s0, 0.25, 1e-12);
  EXPECT_NEAR(f->ssr, 0, 1e-18);
  EXPECT_GT(f->c_var, 0);
  for (auto& p : pts) p.y() = 0.3 - 0.2 * p.x();
  const auto g = fit_broken_line(pts, 0.5);
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->c, 0, 1e-9);
}

}  // namespace test_border_kink
