// Issue 17 experiment driver (session 9): why tags that are readable from their true corners get no
// candidate quad on the realistic set. For every tag the default profile loses at `no_quad`, the
// threshold stage is run again step by step and the tag is put in the first class that fits:
//   border_unknown / border_light   the black border ring is not classed dark (mostly unknown: the
//                                   contrast floor; mostly light: the window sees darker ground)
//   ring_unknown / ring_dark        the white ring is not classed light
//   border_broken                   no one dark component covers 90 % of the border ring
//   ring_broken                     no one light component covers 90 % of the white ring
//   dark_merged                     the border's dark component reaches beyond the white ring (ground)
//   light_leaks_in                  the ring's light component reaches the payload's centre region
//   small_component                 a component under boundaries.min_component_pixels
//   no_group                        no boundary group of the pair (border, ring)
//   fit_failed[:relaxation]         the pair's group gives no quad (and which one relaxed filter gives one)
//   fit_off                         it gives a quad, but not within the loss tolerance of the truth
//   fit_ok                          it gives a matching quad (lost later: refinement, duplicates)
//
// Session 10 appends to each class: whether a group_look window (group_look.hpp) holds the tag
// (|nowin, |win_fail: its one-threshold look finds no matching quad, |win_found), whether an "oracle"
// window centred on the true tag, 1.6 x its size, finds it (oracle_ok / oracle_fail), and the same on
// the image blurred by 0.7 / 1.0 px (b7ok / b10ok).
// Session 11 appends the same oracle window classed against its local mean (threshold.hpp's
// mean_sigma rule; m15 / m25 / m40: sigma 1.5 / 2.5 / 4 px, dead zone 2/255; m25x2: upsampled 2x first;
// m25d5: dead zone 5/255), given to the paper's gradient quads at 1x / 2x (g1ok / g2ok), and to the
// threshold stage upsampled 2x (t2ok). CL_DEBUG=1 prints each mean look's groups, quads and best match.
// Session 14 appends the seed probes (seed_probe.hpp): pD:k, k of 8 quads from the true corners moved by
// D / 10 px that refine and decode; hull:G:ok|shrunk|no, a quad from the hull of one of the G boundary
// groups near the tag; payload:ok|no, the hull of the groups inside the tag scaled by 8/6; cs:k, k of 18
// squares at the true centre with the true area, turned in 5 degree steps, decode; and a line per
// readable tag lost as misread (its quad's error, the truth moved, the quad jittered). SEED_DEBUG=1
// prints each such group's size, offset and quad error.
//
//   candidate_loss FRAMES CEILING_CSV [KEY=V ...]   (KEY=V: the detector variant keys of tagbench raytrace)
// Prints one line per lost tag and the counts per class and size bin (an experiment log, not a results/ CSV).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "codes/families.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/explain_loss.hpp"
#include "detect/find_quads_in_image.hpp"
#include <opencv2/imgproc.hpp>
#include "detect/homography.hpp"
#include "detect/blur.hpp"
#include "detect/group_look.hpp"
#include "detect/low_contrast_quads.hpp"
#include "detect/second_look.hpp"
#include "detect/threshold_quads.hpp"
#include "raytrace/detector_variants.hpp"
#include "realistic/realistic_run.hpp"
#include "realistic/realistic_set.hpp"
#include "seed_probe.hpp"

using namespace tagbench;
using namespace tagbench::bench;

namespace {

std::map<std::pair<int, int>, bool> read_ceiling(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) head.push_back(c);
  }
  auto col = [&](const std::string& n) { return static_cast<std::size_t>(std::find(head.begin(), head.end(), n) - head.begin()); };
  const auto fr = col("frame"), tg = col("tag"), ad = col("area_decoded"), pd = col("point_decoded");
  std::map<std::pair<int, int>, bool> out;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(c);
    out[{std::stoi(v[fr]), std::stoi(v[tg])}] = v[ad] == "1" || v[pd] == "1";
  }
  return out;
}

struct Diagnosis {
  std::string cls, detail;
};

Diagnosis diagnose(const ImageF& img, const Corners& truth, const ThresholdQuadOptions& tq, ThresholdQuadWorkspace& ws) {
  const TernaryImage& t = ws.pass.ternary;
  const Components& comp = ws.pass.components;
  const auto H = tag_homography(truth);
  if (!H) return {"degenerate", ""};
  const Eigen::Matrix3d Hi = H->inverse();
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (const auto& c : truth) xmin = std::min(xmin, c.x()), xmax = std::max(xmax, c.x()), ymin = std::min(ymin, c.y()), ymax = std::max(ymax, c.y());
  const double grow = 0.5 * std::max(xmax - xmin, ymax - ymin);
  const int x0 = std::max(0, static_cast<int>(xmin - grow)), x1 = std::min(img.width - 1, static_cast<int>(xmax + grow));
  const int y0 = std::max(0, static_cast<int>(ymin - grow)), y1 = std::min(img.height - 1, static_cast<int>(ymax + grow));
  // Regions in tag coordinates (black square [-1, 1]^2, 8 cells of 0.25): border ring, white ring, centre.
  int border_n = 0, border_dark = 0, border_light = 0, ring_n = 0, ring_dark = 0, ring_light = 0;
  std::map<std::uint32_t, int> border_lab, ring_lab;
  std::vector<std::pair<int, int>> centre_px;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector3d u = Hi * Eigen::Vector3d(x, y, 1);
      const double r = std::max(std::abs(u.x() / u.z()), std::abs(u.y() / u.z()));
      const auto v = t.at(x, y);
      const auto lab = comp.label_at(x, y);
      if (r >= 0.79 && r <= 0.96) {
        ++border_n, border_dark += v == kTernaryDark, border_light += v == kTernaryLight;
        if (v == kTernaryDark) ++border_lab[lab];
      } else if (r >= 1.04 && r <= 1.21) {
        ++ring_n, ring_dark += v == kTernaryDark, ring_light += v == kTernaryLight;
        if (v == kTernaryLight) ++ring_lab[lab];
      } else if (r < 0.5) {
        centre_px.emplace_back(x, y);
      }
    }
  char buf[256];
  std::snprintf(buf, sizeof buf, "border d/l/n %d/%d/%d ring d/l/n %d/%d/%d", border_dark, border_light, border_n,
                ring_dark, ring_light, ring_n);
  std::string detail = buf;
  if (border_n == 0 || ring_n == 0) return {"tiny", detail};
  if (border_dark < 0.6 * border_n)
    return {border_light > border_n - border_dark - border_light ? "border_light" : "border_unknown", detail};
  if (ring_light < 0.6 * ring_n) return {ring_dark > ring_n - ring_dark - ring_light ? "ring_dark" : "ring_unknown", detail};
  auto top = [](const std::map<std::uint32_t, int>& m) {
    std::pair<std::uint32_t, int> b{kNoComponent, 0};
    for (const auto& [k, v] : m) if (v > b.second) b = {k, v};
    return b;
  };
  const auto [D, dn] = top(border_lab);
  const auto [L, ln] = top(ring_lab);
  const double square_area = 0.5 * std::abs((truth[2] - truth[0]).x() * (truth[3] - truth[1]).y() -
                                            (truth[2] - truth[0]).y() * (truth[3] - truth[1]).x());
  std::snprintf(buf, sizeof buf, " D %d/%d size %u (square %.0f) L %d/%d size %u", dn, border_dark, comp.size[D],
                square_area, ln, ring_light, comp.size[L]);
  detail += buf;
  const bool merged = comp.size[D] > 1.15 * square_area;
  bool leaks = false;
  for (const auto& [x, y] : centre_px) leaks |= comp.label_at(x, y) == L;
  if (dn < 0.9 * border_dark) return {"border_broken", detail};
  if (ln < 0.9 * ring_light) return {merged ? "ring_broken+dark_merged" : "ring_broken", detail};
  if (merged) return {leaks ? "dark_merged+light_leaks" : "dark_merged", detail};
  if (leaks) return {"light_leaks_in", detail};
  if (comp.size[D] < tq.boundaries.min_component_pixels || comp.size[L] < tq.boundaries.min_component_pixels)
    return {"small_component", detail};
  // The pair's group.
  const BoundaryGroups& g = ws.pass.groups;
  std::size_t gi = g.count();
  for (std::size_t k = 0; k < g.count() && gi == g.count(); ++k) {
    const auto& p = g.group(k)[0];
    const int dx = (p.x2 - p.gx) / 2, dy = (p.y2 - p.gy) / 2, lx = dx + p.gx, ly = dy + p.gy;
    if (comp.label_at(dx, dy) == D && comp.label_at(lx, ly) == L) gi = k;
  }
  if (gi == g.count()) return {"no_group", detail};
  std::snprintf(buf, sizeof buf, " group %zu pts", g.group(gi).size());
  detail += buf;
  const double tol = default_loss_tolerance(truth);
  auto fit_one = [&](const QuadFitOptions& f) -> double {
    BoundaryGroups one;
    one.points.assign(g.group(gi).begin(), g.group(gi).end());
    one.offsets = {0, static_cast<std::uint32_t>(one.points.size())};
    std::vector<Quad> q;
    fit_quads(one, img, f, ws.fit, q);
    double best = HUGE_VAL;
    for (const auto& x : q) best = std::min(best, best_corner_match(x.corners, truth));
    return best;
  };
  const QuadFitOptions base = quad_fit_options_for(tq.fit, false);
  const double d = fit_one(base);
  if (d <= tol) return {"fit_ok", detail};
  if (std::isfinite(d)) {
    std::snprintf(buf, sizeof buf, " off %.1f px", d);
    return {"fit_off", detail + buf};
  }
  std::vector<std::pair<std::string, QuadFitOptions>> relax;
  { auto f = base; f.max_line_fit_mse *= 4; relax.emplace_back("mse", f); }
  { auto f = base; f.min_angle_deg = 3; relax.emplace_back("angle", f); }
  { auto f = base; f.min_points = 8; relax.emplace_back("min_points", f); }
  { auto f = base; f.max_maxima = 20; relax.emplace_back("maxima", f); }
  { auto f = base; f.min_tag_width = 3; relax.emplace_back("width", f); }
  std::string cls = "fit_failed";
  for (const auto& [n, f] : relax)
    if (fit_one(f) <= tol) cls += ":" + n;
  return {cls, detail};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: candidate_loss FRAMES CEILING_CSV [KEY=V ...]\n");
    return 2;
  }
  const int frames = std::stoi(argv[1]);
  const auto ceiling = read_ceiling(argv[2]);
  DetectorOptions opt = detector_options_from_args(std::span<char* const>(argv + 3, static_cast<std::size_t>(argc - 3)));
  opt.families = {"36h11"};
  const Detector det(opt);
  const TagFamily fam = load_family("36h11");
  RealisticSettings rs;
  std::map<std::string, std::map<std::string, int>> counts;  // class -> bin -> n
  std::map<std::string, int> stages;
  ThresholdQuadWorkspace ws;
  double cs_ms = 0;  // session 14: time of the centre-and-scale probe's refine-and-decode trials
  int cs_trials = 0;
  for (int fi = 0; fi < frames; ++fi) {
    const RealisticFrame f = make_realistic_frame(rs, fi);
    const ImageF img = to_float_image(f.image);
    DetectorTrace trace;
    const auto dets = det.detect(img, &trace);
    bool ran = false;
    for (std::size_t ti = 0; ti < f.tags.size(); ++ti) {
      const auto& tag = f.tags[ti];
      const auto e = explain_loss(TagTruth{&fam, tag.id, tag.corners}, trace, dets, opt);
      const auto it = ceiling.find({fi, static_cast<int>(ti)});
      const bool readable = it != ceiling.end() && it->second;
      stages[std::string(loss_stage_name(e.stage)) + (readable ? " readable" : " unreadable")]++;
      if (e.stage == LossStage::kMisread && readable) {  // session 14: how far off is a misread quad?
        double off = HUGE_VAL;
        Corners best_q{};
        for (const Quad& q : trace.quads)
          if (const double d = best_corner_match(q.corners, tag.corners); d < off) off = d, best_q = q.corners;
        std::printf("misread frame %d tag %zu px %.1f tilt %.0f: %s; quad off %.2f px; truth moved 0.5/1 px decodes %d/%d of 8;"
                    " quad jittered 1 px decodes %d of 16 (%d refined)\n",
                    fi, ti, tag.black_square_px, tag.tilt_deg, e.text.c_str(), off,
                    perturbed_truth_decodes(img, tag.corners, tag.id, fam, opt, 0.5, 8, 1),
                    perturbed_truth_decodes(img, tag.corners, tag.id, fam, opt, 1.0, 8, 1),
                    jitter_decodes(img, best_q, tag.id, fam, opt, 1.0, false), jitter_decodes(img, best_q, tag.id, fam, opt, 1.0, true));
      }
      if (e.stage != LossStage::kNoQuad || !readable) continue;
      if (!ran) {
        std::vector<Quad> q;
        find_threshold_quads(img, opt.threshold_quads, ws, q);
        ran = true;
      }
      Diagnosis dg = diagnose(img, tag.corners, opt.threshold_quads, ws);
      {  // session 10: does a group_look window hold the tag, and does a window's Otsu look find it?
        GroupLookOptions gl = opt.group_look;
        gl.enabled = true;
        const auto wins = group_look_windows(ws.pass.groups, trace.quads, img.width, img.height, gl);
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (const auto& p : tag.corners) c += p / 4;
        SecondLookOptions sl = opt.second_look;
        sl.max_size_px = HUGE_VAL, sl.margin_px = 0, sl.inside_only = false;
        const double tol = default_loss_tolerance(tag.corners);
        auto finds = [&](const std::vector<Quad>& w, const ImageF* im = nullptr) {
          double best = HUGE_VAL;
          for (const Quad& q : second_look_quads(im ? *im : img, w, std::vector<bool>(w.size(), true), opt.threshold_quads, sl))
            best = std::min(best, best_corner_match(q.corners, tag.corners));
          return best <= tol;
        };
        std::vector<Quad> hold;
        for (const Quad& w : wins)
          if (c.x() >= w.corners[0].x() && c.x() <= w.corners[2].x() && c.y() >= w.corners[0].y() && c.y() <= w.corners[2].y()) hold.push_back(w);
        Quad oracle;
        const double half = 0.8 * tag.black_square_px + 3;
        oracle.corners = {Eigen::Vector2d(c.x() - half, c.y() - half), Eigen::Vector2d(c.x() + half, c.y() - half),
                          Eigen::Vector2d(c.x() + half, c.y() + half), Eigen::Vector2d(c.x() - half, c.y() + half)};
        for (auto& p : oracle.corners) p = p.cwiseMax(Eigen::Vector2d(0, 0)).cwiseMin(Eigen::Vector2d(img.width - 1, img.height - 1));
        const bool got = !hold.empty() && finds(hold), ora = finds({oracle});
        ImageF b7, b10, tmp;
        gaussian_blur(img, 0.7, tmp, b7);
        gaussian_blur(img, 1.0, tmp, b10);
        const bool o7 = finds({oracle}, &b7), o10 = finds({oracle}, &b10);
        dg.cls += std::string(hold.empty() ? " |nowin" : got ? " |win_found" : " |win_fail") + (ora ? " oracle_ok" : " oracle_fail");
        dg.cls += std::string(o7 ? " b7ok" : " b7no") + (o10 ? " b10ok" : " b10no");
        // Session 11: the oracle window upsampled by `up` and given to the paper's gradient quads
        // (g1/g2) or the threshold stage (t2); quads mapped back to the frame.
        auto window_finds = [&](int up, bool gradient) {
          const int wx0 = std::max(0, static_cast<int>(c.x() - half)), wy0 = std::max(0, static_cast<int>(c.y() - half));
          const int wx1 = std::min(img.width - 1, static_cast<int>(c.x() + half) + 1);
          const int wy1 = std::min(img.height - 1, static_cast<int>(c.y() + half) + 1);
          cv::Mat win(wy1 - wy0 + 1, wx1 - wx0 + 1, CV_32F);
          for (int y = wy0; y <= wy1; ++y)
            for (int x = wx0; x <= wx1; ++x) win.at<float>(y - wy0, x - wx0) = img.at(x, y);
          cv::Mat big;
          cv::resize(win, big, cv::Size(), up, up, up == 1 ? cv::INTER_NEAREST : cv::INTER_CUBIC);
          ImageF w(big.cols, big.rows);
          for (int y = 0; y < big.rows; ++y)
            for (int x = 0; x < big.cols; ++x) w.at(x, y) = big.at<float>(y, x);
          std::vector<Quad> qs;
          if (gradient) {
            DetectorOptions p = DetectorOptions::paper();
            DetectorWorkspace dw;
            qs = find_quads_in_image(w, p, dw).quads;
          } else {
            ThresholdQuadWorkspace tw;
            ThresholdQuadOptions tq = opt.threshold_quads;
            tq.fit.min_tag_width *= up;
            find_threshold_quads(w, tq, tw, qs);
          }
          double best = HUGE_VAL;
          for (Quad q : qs) {
            for (auto& p : q.corners) p = Eigen::Vector2d(wx0 + (p.x() + 0.5) / up - 0.5, wy0 + (p.y() + 0.5) / up - 0.5);
            best = std::min(best, best_corner_match(q.corners, tag.corners));
          }
          return best <= tol;
        };
        // Local-mean classing: light where I - G_sigma*I > delta, dark where < -delta, else unknown.
        auto mean_finds = [&](double sigma, float delta, int up) {
          const int m = 6;
          const int wx0 = std::max(0, static_cast<int>(c.x() - half) - m), wy0 = std::max(0, static_cast<int>(c.y() - half) - m);
          const int wx1 = std::min(img.width - 1, static_cast<int>(c.x() + half) + 1 + m);
          const int wy1 = std::min(img.height - 1, static_cast<int>(c.y() + half) + 1 + m);
          cv::Mat win(wy1 - wy0 + 1, wx1 - wx0 + 1, CV_32F);
          for (int y = wy0; y <= wy1; ++y)
            for (int x = wx0; x <= wx1; ++x) win.at<float>(y - wy0, x - wx0) = img.at(x, y);
          if (up > 1) cv::resize(win, win, cv::Size(), up, up, cv::INTER_CUBIC);
          cv::Mat mean;
          cv::GaussianBlur(win, mean, cv::Size(0, 0), sigma * up);
          ImageF roi(win.cols, win.rows);
          TernaryImage tern;
          tern.width = win.cols, tern.height = win.rows;
          tern.data.resize(roi.data.size());
          for (int y = 0; y < win.rows; ++y)
            for (int x = 0; x < win.cols; ++x) {
              const float v = win.at<float>(y, x), d = v - mean.at<float>(y, x);
              roi.at(x, y) = v;
              tern.data[static_cast<std::size_t>(y) * win.cols + x] = d > delta ? kTernaryLight : d < -delta ? kTernaryDark : kTernaryUnknown;
            }
          ComponentScratch cs;
          Components comp;
          BoundaryScratch bs;
          BoundaryGroups groups;
          QuadFitScratch fs;
          EdgeRefineScratch rs;
          std::vector<Quad> qs;
          connected_components(tern, cs, comp, opt.threshold_quads.dark_eight_connected);
          group_boundaries(tern, comp, opt.threshold_quads.boundaries, bs, groups);
          QuadFitOptions fo = opt.threshold_quads.fit;
          fo.min_tag_width *= up;
          fit_quads(groups, roi, fo, fs, qs);
          double best = HUGE_VAL;
          for (Quad q : qs) {
            for (auto& p : q.corners) p = Eigen::Vector2d(wx0 + (p.x() + 0.5) / up - 0.5, wy0 + (p.y() + 0.5) / up - 0.5);
            if (const auto r = refine_quad_edges(img, q.corners, opt.threshold_quads.refine, rs)) q.corners = *r;
            best = std::min(best, best_corner_match(q.corners, tag.corners));
          }
          if (std::getenv("CL_DEBUG"))
            std::fprintf(stderr, "mean sigma %.1f up %d: %zu groups %zu quads best %.2f tol %.2f\n", sigma, up, groups.count(),
                         qs.size(), best, tol);
          return best <= tol;
        };
        dg.cls += std::string(mean_finds(1.5, 2.0f / 255, 1) ? " m15" : " --") + (mean_finds(2.5, 2.0f / 255, 1) ? " m25" : " --") +
                  (mean_finds(4, 2.0f / 255, 1) ? " m40" : " --") + (mean_finds(2.5, 2.0f / 255, 2) ? " m25x2" : " --") +
                  (mean_finds(2.5, 5.0f / 255, 1) ? " m25d5" : " --");
        dg.cls += std::string(window_finds(1, true) ? " g1ok" : " g1no") + (window_finds(2, true) ? " g2ok" : " g2no") +
                  (window_finds(2, false) ? " t2ok" : " t2no");
        // Session 14 (seed_probe.hpp): " pD:k" = k of 8 quads from the true corners moved by D / 10 px
        // refine and decode; " hull:G:ok|shrunk|no" = a quad from the hull of one of the G boundary
        // groups near the tag (or that quad shrunk by 8/10) refines and decodes.
        for (const double d : {0.5, 1.0, 1.5, 2.0, 3.0})
          dg.cls += " p" + std::to_string(static_cast<int>(d * 10)) + ":" +
                    std::to_string(perturbed_truth_decodes(img, tag.corners, tag.id, fam, opt, d, 8,
                                                           static_cast<std::uint32_t>(fi * 1000 + static_cast<int>(ti))));
        int near = 0;
        bool shrunk = false;
        const bool hull = hull_seed_decodes(img, ws.pass.groups, tag.corners, tag.id, fam, opt, near, shrunk);
        dg.cls += " hull:" + std::to_string(near) + (hull ? shrunk ? ":shrunk" : ":ok" : ":no");
        const auto t_cs = std::chrono::steady_clock::now();
        dg.cls += " cs:" + std::to_string(centre_scale_decodes(img, tag.corners, tag.id, fam, opt, 5));
        cs_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_cs).count(), cs_trials += 18;
        double turn = 0;
        const int cst = centre_scale_turn_decodes(img, tag.corners, tag.id, fam, opt, turn);
        dg.cls += " cst:" + std::to_string(cst) + "@" + std::to_string(static_cast<int>(std::lround(turn)));
        dg.cls += payload_hull_decodes(img, ws.pass.groups, tag.corners, tag.id, fam, opt) ? " payload:ok" : " payload:no";
      }
      std::printf("frame %d tag %zu id %d px %.1f tilt %.0f ink %.2f paper %.2f light %.2f blur %.2f: %s  %s\n", fi, ti,
                  tag.id, tag.black_square_px, tag.tilt_deg, tag.ink, tag.paper, tag.light, f.degradation.blur_sigma_px,
                  dg.cls.c_str(), dg.detail.c_str());
      counts[dg.cls][size_bin_of(tag.black_square_px).name]++;
      counts[dg.cls]["all"]++;
    }
  }
  std::printf("\ncentre-and-scale probe: %d trials, %.1f us a trial (edge refinement + decoding)\n", cs_trials,
              cs_trials ? 1000 * cs_ms / cs_trials : 0.0);
  std::printf("\nloss stages (all sizes):\n");
  for (const auto& [k, v] : stages) std::printf("  %-28s %d\n", k.c_str(), v);
  std::printf("\nreadable no_quad tags by class and bin:\n%-28s", "class");
  const char* bins[] = {"12-16", "16-20", "20-24", "24-28", "28-32", "32-40", "all"};
  for (const char* b : bins) std::printf(" %6s", b);
  std::printf("\n");
  for (const auto& [c, m] : counts) {
    std::printf("%-28s", c.c_str());
    for (const char* b : bins) std::printf(" %6d", m.count(b) ? m.at(b) : 0);
    std::printf("\n");
  }
  return 0;
}
