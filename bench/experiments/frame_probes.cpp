// Issue 17 experiment driver (sessions 9-12; moved out of candidate_loss in session 14): whole-frame
// probes of the realistic set.
//   frame_probes time FRAMES [KEY=V ...]   the default profile's stage times summed over the frames (ms)
//   frame_probes regions FRAMES            the faint regions of the low-contrast look and the tag in each
//   frame_probes groups SEED FRAME X Y [R] the default profile's boundary groups within R px of (X, Y) on a
//                                          realistic frame: components, group counts, outline fits with and
//                                          without the ring check (PROBE_DUMP=1: the outline's points;
//                                          PROBE_UNION=1: the groups inside the box joined and fitted;
//                                          PROBE_DQ=1: the joined outlines' quads with overlap_clusters on)
//   frame_probes cover SEED FRAMES [PAD]   the share of each frame inside the boxes (+ PAD px) of tag-sized
//                                          boundary groups without a candidate quad, and of each tag
//                                          (session 36: a cue for where full-resolution edges would pay)
// KEY=V: the detector variant keys of tagbench raytrace. Prints an experiment log, not a results/ CSV.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/components.hpp"
#include "detect/dark_outlines.hpp"
#include "detect/outer_outline.hpp"
#include "detect/quad_fit.hpp"
#include "detect/low_contrast_quads.hpp"
#include "detect/threshold.hpp"
#include "raytrace/detector_variants.hpp"
#include "realistic/realistic_set.hpp"

using namespace tagbench;
using namespace tagbench::bench;

namespace {
Eigen::Vector2d centre(const Quad& q) { return (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]) / 4; }
void print_corners(const char* label, const Corners& c) {
  std::printf("%s %.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f\n", label, c[0].x(), c[0].y(), c[1].x(), c[1].y(), c[2].x(),
              c[2].y(), c[3].x(), c[3].y());
}
}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::string(argv[1]) == "time") {  // frame_probes time FRAMES [KEY=V ...]: stage ms
    DetectorOptions opt = detector_options_from_args(std::span<char* const>(argv + 3, static_cast<std::size_t>(argc - 3)));
    opt.families = {"36h11"};
    const Detector det(opt);
    DetectorWorkspace ws;
    StageTimings sum;
    for (int fi = 0; fi < std::stoi(argv[2]); ++fi) {
      const ImageF img = to_float_image(make_realistic_frame(RealisticSettings{}, fi).image);
      StageTimings tm;
      det.detect(img, ws, nullptr, &tm);
      sum.blur += tm.blur, sum.segmentation += tm.segmentation, sum.quads += tm.quads, sum.line_fit += tm.line_fit;
      sum.decode += tm.decode, sum.total += tm.total, sum.quad_count += tm.quad_count;
    }
    std::printf("blur %.0f threshold+components %.0f boundaries+fit %.0f refine %.0f decode(+look) %.0f total %.0f ms; quads %zu\n",
                sum.blur, sum.segmentation, sum.quads, sum.line_fit, sum.decode, sum.total, sum.quad_count);
    return 0;
  }
  if (argc >= 3 && std::string(argv[1]) == "regions") {  // frame_probes regions FRAMES: faint regions, tags in them
    const DetectorOptions opt;
    LowContrastScratch ls;
    std::vector<FaintRegion> regs;
    for (int fi = 0; fi < std::stoi(argv[2]); ++fi) {
      const RealisticFrame f = make_realistic_frame(RealisticSettings{}, fi);
      const ImageF img = to_float_image(f.image);
      ThresholdScratch th;
      TernaryImage tern;
      adaptive_threshold(img, opt.threshold_quads.threshold, th, tern);
      LowContrastPassOptions all;
      all.min_size_px = 0, all.max_size_px = 1e9, all.min_fill = 0, all.min_area_px = 0;
      faint_regions(th, img.width, img.height, 2, 10.0f / 255, 20.0f / 255, all, ls, regs);
      for (const auto& r : regs) {
        int tag = -1;
        double px = 0;
        for (std::size_t t = 0; t < f.tags.size(); ++t) {
          Eigen::Vector2d c = Eigen::Vector2d::Zero();
          for (const auto& p : f.tags[t].corners) c += p / 4;
          if (c.x() >= r.x0 && c.x() <= r.x1 && c.y() >= r.y0 && c.y() <= r.y1) tag = static_cast<int>(t), px = f.tags[t].black_square_px;
        }
        const int w = r.x1 - r.x0 + 1, h = r.y1 - r.y0 + 1;
        std::printf("R %d %d %d %d %.3f %d %.1f\n", fi, w, h, r.tiles, 4.0 * r.tiles / (w * h), tag, px);
      }
    }
    return 0;
  }
  if (argc >= 4 && std::string(argv[1]) == "cover") {  // frame_probes cover SEED FRAMES [PAD]: failed groups' windows
    RealisticSettings rs;
    rs.seed = std::stoull(argv[2]);
    const int pad = argc >= 5 ? std::stoi(argv[4]) : 3;
    const DetectorOptions opt;
    const Detector det(opt);
    DetectorWorkspace ws;
    double cov_sum = 0;
    for (int fi = 0; fi < std::stoi(argv[3]); ++fi) {
      const RealisticFrame f = make_realistic_frame(rs, fi);
      const ImageF img = to_float_image(f.image);
      DetectorTrace tr;
      det.detect(img, ws, &tr, nullptr);
      std::vector<std::uint8_t> mask(static_cast<std::size_t>(img.width) * img.height, 0);
      const BoundaryGroups& g = tr.boundary_groups;
      for (std::size_t i = 0; i < g.count(); ++i) {
        const DoubledBox b = bounding_box(g.group(i));
        const double w = (b.xmax - b.xmin) / 2.0, h = (b.ymax - b.ymin) / 2.0;
        if (std::max(w, h) < 8 || std::max(w, h) > 50 || static_cast<double>(g.group(i).size()) < 4 * (w + h)) continue;
        bool has_quad = false;
        for (const Quad& q : tr.quads) {
          const Eigen::Vector2d c = centre(q);
          if (c.x() >= b.xmin / 2.0 && c.x() <= b.xmax / 2.0 && c.y() >= b.ymin / 2.0 && c.y() <= b.ymax / 2.0) has_quad = true;
        }
        if (has_quad && !std::getenv("PROBE_ALL")) continue;
        for (int y = std::max(0, b.ymin / 2 - pad); y <= std::min(img.height - 1, b.ymax / 2 + 1 + pad); ++y)
          for (int x = std::max(0, b.xmin / 2 - pad); x <= std::min(img.width - 1, b.xmax / 2 + 1 + pad); ++x)
            mask[static_cast<std::size_t>(y) * img.width + x] = 1;
      }
      std::size_t on = 0;
      for (const auto m : mask) on += m;
      const double cov = static_cast<double>(on) / static_cast<double>(mask.size());
      cov_sum += cov;
      for (std::size_t t = 0; t < f.tags.size(); ++t) {
        double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
        for (const auto& p : f.tags[t].corners) x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
        std::size_t in = 0, all = 0;
        for (int y = static_cast<int>(std::ceil(y0)); y <= static_cast<int>(y1); ++y)
          for (int x = static_cast<int>(std::ceil(x0)); x <= static_cast<int>(x1); ++x, ++all) in += mask[static_cast<std::size_t>(y) * img.width + x];
        std::printf("T %d %zu %.2f %.3f\n", fi, t, f.tags[t].black_square_px, all ? static_cast<double>(in) / all : 0.0);
      }
      std::printf("F %d %.4f\n", fi, cov);
    }
    std::printf("mean coverage %.4f\n", cov_sum / std::stoi(argv[3]));
    return 0;
  }
  if (argc >= 6 && std::string(argv[1]) == "groups") {  // frame_probes groups SEED FRAME X Y [R]: groups near a point
    RealisticSettings rs;
    rs.seed = std::stoull(argv[2]);
    const RealisticFrame f = make_realistic_frame(rs, std::stoi(argv[3]));
    const double px = std::stod(argv[4]), py = std::stod(argv[5]), rad = argc >= 7 ? std::stod(argv[6]) : 14;
    const ImageF img = to_float_image(f.image);
    const DetectorOptions opt;
    const Detector det(opt);
    DetectorWorkspace ws;
    DetectorTrace tr;
    det.detect(img, ws, &tr, nullptr);
    ComponentScratch cs;
    Components comp;
    connected_components(tr.threshold_classes, cs, comp, opt.threshold_quads.dark_eight_connected);
    const BoundaryGroups& g = tr.boundary_groups;
    std::vector<std::uint32_t> dark_of(g.count()), light_of(g.count());
    for (std::size_t i = 0; i < g.count(); ++i) {
      const BoundaryPoint& p = g.group(i).front();
      dark_of[i] = comp.label_at((p.x2 - p.gx) / 2, (p.y2 - p.gy) / 2);
      light_of[i] = comp.label_at((p.x2 + p.gx) / 2, (p.y2 + p.gy) / 2);
    }
    QuadFitScratch fs;
    if (std::getenv("PROBE_DQ")) {  // the joined outlines' quads near the point, overlap clusters on
      DarkOutlineOptions dq = opt.dark_outlines;
      dq.overlap_clusters = true;
      dq.check_before_refining = false;
      DarkOutlineScratch ds;
      const auto quads = dark_outline_quads(g, comp, img, {}, opt.threshold_quads.fit, opt.threshold_quads.refine, dq, fs, ds);
      for (std::size_t k = 0; k < ds.joined.count(); ++k) {
        const DoubledBox b = bounding_box(ds.joined.group(k));
        if (b.xmax / 2.0 < px - rad || b.xmin / 2.0 > px + rad || b.ymax / 2.0 < py - rad || b.ymin / 2.0 > py + rad) continue;
        std::printf("joined %zu: %zu pts box %.1f..%.1f x %.1f..%.1f\n", k, ds.joined.group(k).size(), b.xmin / 2.0, b.xmax / 2.0, b.ymin / 2.0, b.ymax / 2.0);
      }
      for (const Quad& q : quads) {
        const Eigen::Vector2d c = centre(q);
        if (std::abs(c.x() - px) > rad || std::abs(c.y() - py) > rad) continue;
        print_corners("quad", q.corners);
      }
      return 0;
    }
    if (std::getenv("PROBE_UNION")) {  // the union of the groups whose box lies inside the square (px +- rad)
      std::vector<BoundaryPoint> u;
      int n = 0;
      for (std::size_t i = 0; i < g.count(); ++i) {
        const DoubledBox b = bounding_box(g.group(i));
        if (b.xmin / 2.0 < px - rad || b.xmax / 2.0 > px + rad || b.ymin / 2.0 < py - rad || b.ymax / 2.0 > py + rad) continue;
        if (g.group(i).size() < 8) continue;
        u.insert(u.end(), g.group(i).begin(), g.group(i).end()), ++n;
      }
      QuadFitOptions nr = opt.threshold_quads.fit;
      outer_outline_points(u, nr.outer, fs.outer, fs.side, 4);
      const auto c = fit_outline(fs.side, img, nr, fs);
      nr.outer.ring_check = false;
      const auto c_nr = fit_outline(fs.side, img, nr, fs);
      std::printf("union of %d groups, %zu pts: fit %s ring-off %s\n", n, u.size(), c ? "yes" : "no", c_nr ? "yes" : "no");
      if (c_nr) print_corners("   ringoff corners", *c_nr);
      return 0;
    }
    for (std::size_t i = 0; i < g.count(); ++i) {
      const DoubledBox b = bounding_box(g.group(i));
      const double x0 = b.xmin / 2.0, x1 = b.xmax / 2.0, y0 = b.ymin / 2.0, y1 = b.ymax / 2.0;
      if (x1 < px - rad || x0 > px + rad || y1 < py - rad || y0 > py + rad) continue;
      int nd = 0, nl = 0;
      for (std::size_t j = 0; j < g.count(); ++j) nd += dark_of[j] == dark_of[i], nl += light_of[j] == light_of[i];
      outer_outline_points(g.group(i), opt.threshold_quads.fit.outer, fs.outer, fs.side,
                           static_cast<std::size_t>(std::max(opt.threshold_quads.fit.min_points, 4)));
      const auto c = fit_outline(fs.side, img, opt.threshold_quads.fit, fs);
      QuadFitOptions nr = opt.threshold_quads.fit;
      nr.outer.ring_check = false;
      const auto c_nr = fit_outline(fs.side, img, nr, fs);
      QuadFitOptions loose = nr;
      loose.max_line_fit_mse = 1e9, loose.min_angle_deg = 0;
      const auto c_lo = fit_outline(fs.side, img, loose, fs);
      const auto c_whole = fit_quad(g.group(i), img, nr, fs);
      if (std::getenv("PROBE_DUMP"))
        for (const auto& p : fs.side) std::printf("  P %.1f %.1f\n", p.x2 / 2.0, p.y2 / 2.0);
      std::printf("   ring-off %s loose %s whole %s\n", c_nr ? "yes" : "no", c_lo ? "yes" : "no", c_whole ? "yes" : "no");
      if (c_nr) print_corners("   ringoff corners", *c_nr);
      std::printf("group %zu: %zu pts box %.1f..%.1f x %.1f..%.1f dark %u (%u px, %d groups) light %u (%u px, %d groups) outer %zu fit %s\n",
                  i, g.group(i).size(), x0, x1, y0, y1, dark_of[i], dark_of[i] < comp.size.size() ? comp.size[dark_of[i]] : 0, nd,
                  light_of[i], light_of[i] < comp.size.size() ? comp.size[light_of[i]] : 0, nl, fs.side.size(), c ? "yes" : "no");
    }
    return 0;
  }
  std::fprintf(stderr, "usage: frame_probes time FRAMES [KEY=V ...] | regions FRAMES | groups SEED FRAME X Y [R] | cover SEED FRAMES [PAD]\n");
  return 2;
}
