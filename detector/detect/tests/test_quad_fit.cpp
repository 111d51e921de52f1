#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "detect/quad_fit.hpp"
#include "detect/threshold_quads.hpp"
#include "synthetic.hpp"
#include "synthetic_tag.hpp"

namespace test_quad_fit {

using namespace tagbench;

namespace {
// A dark quad (clockwise on screen) on light ground, anti-aliased, with mild noise.
ImageF scene(const Corners& c, int w, int h, float dark = 0.15f, float light = 0.85f, double noise = 0.002) {
  ImageF img = synth::render_convex_polygon(w, h, {c[0], c[1], c[2], c[3]}, dark, light, 8);
  if (noise > 0) synth::add_gaussian_noise(img, noise, 7);
  return img;
}
Corners tilted(double cx, double cy, double a, double phi) {  // clockwise on screen, first corner top-left at phi = 0
  const Eigen::Vector2d u(std::cos(phi), std::sin(phi)), v(-std::sin(phi), std::cos(phi)), c(cx, cy);
  return {c + a * (-u - v), c + a * (u - v), c + a * (u + v), c + a * (-u + v)};
}
// Max over the true corners of the distance to the nearest found corner; also checks the cyclic order.
double corner_error(const Corners& found, const Corners& truth) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < 4; ++i)
    if ((found[i] - truth[0]).norm() < (found[k] - truth[0]).norm()) k = i;
  double e = 0;
  for (std::size_t i = 0; i < 4; ++i) e = std::max(e, (found[(k + i) % 4] - truth[i]).norm());
  return e;
}
}  // namespace

TEST(QuadFit, FindsARotatedSquareClockwiseToAFractionOfAPixel) {
  const Corners truth = tilted(40.3, 35.7, 14, 0.35);
  const ImageF img = scene(truth, 80, 70);
  std::vector<Quad> quads;
  ThresholdQuadWorkspace ws;
  ThresholdQuadOptions opt;
  opt.refine_edges = false;
  find_threshold_quads(img, opt, ws, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_LT(corner_error(quads[0].corners, truth), 0.6);
  const auto& q = quads[0].corners;  // clockwise on screen: positive cross product with y down
  EXPECT_GT((q[1] - q[0]).x() * (q[2] - q[1]).y() - (q[1] - q[0]).y() * (q[2] - q[1]).x(), 0);
  opt.refine_edges = true;
  find_threshold_quads(img, opt, ws, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_LT(corner_error(quads[0].corners, truth), 0.25);
}

// ThresholdQuadOptions::refine_check: a quad whose border passes the decoder's pre-filter is refined
// as without the check; one it refuses (a floor above the square's contrast) is left as fitted.
// The Detector fills the check from its families and PayloadOptions.
TEST(QuadFit, RefineCheckLeavesOnlyImplausibleBordersUnrefined) {
  const Corners truth = tilted(40.3, 35.7, 14, 0.35);
  const ImageF img = scene(truth, 80, 70);
  ThresholdQuadWorkspace ws;
  std::vector<Quad> fitted, refined, checked;
  ThresholdQuadOptions opt;
  opt.refine_edges = false;
  find_threshold_quads(img, opt, ws, fitted);
  opt.refine_edges = true;
  find_threshold_quads(img, opt, ws, refined);
  opt.refine_check.enabled = true;
  find_threshold_quads(img, opt, ws, checked);
  ASSERT_EQ(fitted.size(), 1u);
  ASSERT_EQ(checked.size(), 1u);
  ASSERT_EQ(refined.size(), 1u);
  EXPECT_NE(refined[0].corners, fitted[0].corners);
  EXPECT_EQ(checked[0].corners, refined[0].corners);
  opt.refine_check.min_contrast = 0.9;  // the square's contrast is 0.7
  find_threshold_quads(img, opt, ws, checked);
  ASSERT_EQ(checked.size(), 1u);
  EXPECT_EQ(checked[0].corners, fitted[0].corners);

  DetectorOptions o;
  o.families = {"16h5"};
  o.payload.min_contrast = 0.05;
  const Detector det(o);
  const auto& c = det.options().threshold_quads.refine_check;
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.payload_width, 4);
  EXPECT_EQ(c.min_contrast, 0.05);
  o.families = {"16h5", "36h11"};
  EXPECT_EQ(Detector(o).options().threshold_quads.refine_check.payload_width, 6);
  o.payload.quick_reject = false;
  EXPECT_FALSE(Detector(o).options().threshold_quads.refine_check.enabled);
}

TEST(QuadFit, PerspectiveQuadAndHalvedStage) {
  const Corners truth = {Eigen::Vector2d(30.2, 22.9), Eigen::Vector2d(95.6, 30.1), Eigen::Vector2d(88.3, 80.4),
                         Eigen::Vector2d(36.7, 71.2)};
  const ImageF img = scene(truth, 128, 100);
  ThresholdQuadWorkspace ws;
  std::vector<Quad> quads;
  ThresholdQuadOptions opt;
  opt.halve = true;
  find_threshold_quads(img, opt, ws, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_LT(corner_error(quads[0].corners, truth), 0.3);  // refined on the full image
  EXPECT_NEAR(quads[0].observed_perimeter, 65.8 + 51.1 + 52.1 + 49.3, 3.0);
}

TEST(QuadFit, RejectsLightSquaresUnlessAskedTooSmallOnesAndNonQuads) {
  const Corners c = tilted(30, 30, 10, 0.2);
  const ImageF light_in = scene(c, 60, 60, 0.85f, 0.15f);
  ThresholdQuadWorkspace ws;
  std::vector<Quad> quads;
  ThresholdQuadOptions opt;
  find_threshold_quads(light_in, opt, ws, quads);
  EXPECT_TRUE(quads.empty());
  opt.fit.light_inside = true;
  opt.fit.dark_inside = false;
  find_threshold_quads(light_in, opt, ws, quads);
  EXPECT_EQ(quads.size(), 1u);

  opt = {};
  opt.fit.min_tag_width = 25;  // the square is 20 px: below
  find_threshold_quads(scene(c, 60, 60), opt, ws, quads);
  EXPECT_TRUE(quads.empty());

  // A triangle and a disc are not quads.
  opt = {};
  const ImageF tri = synth::render_convex_polygon(60, 60, {{10, 50}, {30, 10}, {50, 50}}, 0.15f, 0.85f, 8);
  find_threshold_quads(tri, opt, ws, quads);
  EXPECT_TRUE(quads.empty());
  std::vector<Eigen::Vector2d> disc;
  for (int i = 0; i < 64; ++i) disc.emplace_back(30 + 18 * std::cos(i * M_PI / 32), 30 + 18 * std::sin(i * M_PI / 32));
  find_threshold_quads(synth::render_convex_polygon(60, 60, disc, 0.15f, 0.85f, 8), opt, ws, quads);
  EXPECT_TRUE(quads.empty());
}

TEST(QuadFit, TagLikeFrameGivesTheOuterSquareAndWorkspaceIsReused) {
  // A dark square with a light square inside (the inner boundary is light-inside: rejected).
  const Corners outer = tilted(50, 50, 20, 0.1), inner = tilted(50, 50, 10, 0.1);
  ImageF img = synth::render_convex_polygon(100, 100, {outer[0], outer[1], outer[2], outer[3]}, 0.1f, 0.9f, 8);
  const ImageF in = synth::render_convex_polygon(100, 100, {inner[0], inner[1], inner[2], inner[3]}, 1.0f, 0.0f, 8);
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = std::max(img.data[i], 0.9f * in.data[i]);
  ThresholdQuadWorkspace ws;
  std::vector<Quad> quads;
  find_threshold_quads(img, {}, ws, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_LT(corner_error(quads[0].corners, outer), 0.25);
  const auto before = std::vector<const void*>{ws.pass.ternary.data.data(), ws.pass.components.runs.data(),
                                               ws.pass.groups.points.data(), ws.pass.boundary_scratch.keys.data()};
  find_threshold_quads(img, {}, ws, quads);
  const auto after = std::vector<const void*>{ws.pass.ternary.data.data(), ws.pass.components.runs.data(),
                                              ws.pass.groups.points.data(), ws.pass.boundary_scratch.keys.data()};
  EXPECT_EQ(before, after);
}

TEST(QuadFit, TinyAndRandomImagesRunCleanly) {
  // Every size from 1 x 1 up (the 8-pixel skip, partial tiles, halving below 4 px) and random noise
  // with the halved pass: no crash, no sanitizer report, and every quad inside the image.
  ThresholdQuadWorkspace ws;
  std::vector<Quad> quads;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  for (int w = 1; w <= 19; w += 3)
    for (int h = 1; h <= 13; h += 4) {
      ImageF img(w, h);
      for (float& v : img.data) v = u(rng);
      for (bool halve : {false, true}) {
        ThresholdQuadOptions opt;
        opt.halve = halve;
        opt.threshold.tile_size = 1 + (w + h) % 5;
        EXPECT_NO_THROW(find_threshold_quads(img, opt, ws, quads));
      }
    }
  ImageF noise(160, 120);
  for (float& v : noise.data) v = u(rng) < 0.5f ? 0.1f : 0.9f;
  for (bool halve : {false, true}) {
    ThresholdQuadOptions opt;
    opt.halve = halve;
    opt.boundaries.min_component_pixels = 1;
    opt.fit.min_tag_width = 3;
    find_threshold_quads(noise, opt, ws, quads);
    for (const Quad& q : quads)
      for (const auto& c : q.corners) {
        EXPECT_TRUE(std::isfinite(c.x()) && std::isfinite(c.y()));
      }
  }
}

// Tags at the edge of range (issue 17): a 36h11 tag whose black square is 10 px has a black border
// and a white ring 1.25 px wide. Rotated, the border is a diagonal staircase that the threshold and
// 4-connected dark regions cut into pieces; with dark_eight_connected the square's outline is one
// group again. Counted over rotations and ids so that the option's effect, not one lucky frame, is
// tested.
TEST(QuadFit, DarkEightConnectedFindsTenPixelTagsAtEveryRotation) {
  const TagFamily& f = builtin_family("36h11");
  int found4 = 0, found8 = 0, n = 0;
  for (int k = 0; k < 18; ++k) {
    const double phi = k * 5.0 * M_PI / 180.0;  // 0..85 degrees
    const Corners truth = synth::square_tag_corners(32.3 + 0.17 * k, 30.6 - 0.11 * k, 10.0, phi);
    const ImageF img =
        synth::render_tag(64, 64, tag_cells(f, 11 + 31 * k), synth::homography_for(truth), 0.5f, 8, 0.0f, 1.0f);
    ThresholdQuadWorkspace ws;
    std::vector<Quad> quads;
    for (const bool dark8 : {false, true}) {
      ThresholdQuadOptions opt;
      opt.dark_eight_connected = dark8;
      find_threshold_quads(img, opt, ws, quads);
      bool hit = false;
      for (const Quad& q : quads) hit = hit || corner_error(q.corners, truth) < 1.0;
      (dark8 ? found8 : found4) += hit;
    }
    ++n;
  }
  EXPECT_EQ(found8, n);
  EXPECT_LT(found4, found8);
}

// refit_one_side: one group holding two nested outlines (the square's edge, dark inside, and a
// ring's outer edge around it, light inside) fits no quad; its outward points alone are the square.
TEST(QuadFit, RefitOneSideFindsTheSquareInsideAMixedGroup) {
  BoundaryGroups groups;
  auto outline = [&](int c2, int half2, int sign) {  // doubled coordinates, centre c2, half side half2
    for (int t = -half2; t < half2; ++t) {
      groups.points.push_back({c2 + t, c2 - half2, 0, static_cast<std::int8_t>(-sign)});   // top
      groups.points.push_back({c2 + half2, c2 + t, static_cast<std::int8_t>(sign), 0});    // right
      groups.points.push_back({c2 - t, c2 + half2, 0, static_cast<std::int8_t>(sign)});    // bottom
      groups.points.push_back({c2 - half2, c2 - t, static_cast<std::int8_t>(-sign), 0});   // left
    }
  };
  outline(80, 20, 1);   // the square: 20 px wide at (40, 40), light outside
  outline(80, 30, -1);  // the ring's outer edge: 30 px wide, light inside
  groups.offsets = {0, static_cast<std::uint32_t>(groups.points.size())};
  std::vector<BoundaryPoint> side;
  one_side_points(groups.group(0), true, side);
  EXPECT_EQ(side.size(), 160u);
  for (const auto& p : side) EXPECT_LE(std::max(std::abs(p.x2 - 80), std::abs(p.y2 - 80)), 20);

  const ImageF img(80, 80, 0.5f);
  QuadFitScratch s;
  QuadFitOptions opt;
  std::vector<Quad> quads;
  fit_quads(groups, img, opt, s, quads);
  EXPECT_TRUE(quads.empty());
  opt.refit_one_side = true;
  fit_quads(groups, img, opt, s, quads);
  ASSERT_EQ(quads.size(), 1u);
  EXPECT_LT(corner_error(quads[0].corners, tilted(40, 40, 10, 0)), 0.6);
}

// The kernel errors (two points at a time with SSE2) are the scalar formula's numbers bit for bit:
// cumulative moments of random weighted points, odd and even spans, collinear runs (error 0 or a
// rounding residue, where max(0, .) matters).
TEST(QuadFit, KernelErrorsEqualTheScalarFormulaBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int trial = 0; trial < 100; ++trial) {
    const int n = 30 + static_cast<int>(u01(rng) * 200), k = 2 + static_cast<int>(u01(rng) * 10);
    std::vector<QuadFitScratch::Moments> cum(static_cast<std::size_t>(n));
    QuadFitScratch::Moments m{};
    for (int i = 0; i < n; ++i) {
      // Every third trial on a line (x = y), else scattered; weights as the fit gives them (>= 1).
      const double x = trial % 3 == 0 ? i * 0.5 : 40 * u01(rng), y = trial % 3 == 0 ? i * 0.5 : 40 * u01(rng);
      const double w = 1 + 200 * u01(rng);
      m.mx += w * x, m.my += w * y, m.mxx += w * x * x, m.mxy += w * x * y, m.myy += w * y * y, m.w += w;
      cum[static_cast<std::size_t>(i)] = m;
    }
    const int lo = k + 1, hi = n - k;
    std::vector<double> got(static_cast<std::size_t>(n), -1.0);
    detail::kernel_errors(cum.data(), k, lo, hi, got.data());
    for (int i = lo; i < hi; ++i) {
      const auto& a = cum[static_cast<std::size_t>(i + k)];
      const auto& b = cum[static_cast<std::size_t>(i - k - 1)];
      const double mx = a.mx - b.mx, my = a.my - b.my, mxx = a.mxx - b.mxx, mxy = a.mxy - b.mxy,
                   myy = a.myy - b.myy, mw = a.w - b.w;
      const double ex = mx / mw, ey = my / mw;
      const double cxx = mxx / mw - ex * ex, cxy = mxy / mw - ex * ey, cyy = myy / mw - ey * ey;
      const double root = std::sqrt((cxx - cyy) * (cxx - cyy) + 4 * cxy * cxy);
      const double want = (2 * k + 1) * std::max(0.0, 0.5 * (cxx + cyy - root));
      EXPECT_EQ(got[static_cast<std::size_t>(i)], want) << trial << " " << i;
    }
    EXPECT_EQ(got[static_cast<std::size_t>(lo - 1)], -1.0);  // nothing written outside [lo, hi)
    EXPECT_EQ(got[static_cast<std::size_t>(hi)], -1.0);
  }
}

}  // namespace test_quad_fit
