// Issue 17 experiment driver (sessions 9-12; moved out of candidate_loss in session 14): whole-frame
// probes of the realistic set.
//   frame_probes time FRAMES [KEY=V ...]   the default profile's stage times summed over the frames (ms)
//   frame_probes regions FRAMES            the faint regions of the low-contrast look and the tag in each
// KEY=V: the detector variant keys of tagbench raytrace. Prints an experiment log, not a results/ CSV.
#include <cstdio>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/low_contrast_quads.hpp"
#include "detect/threshold.hpp"
#include "raytrace/detector_variants.hpp"
#include "realistic/realistic_set.hpp"

using namespace tagbench;
using namespace tagbench::bench;

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
  std::fprintf(stderr, "usage: frame_probes time FRAMES [KEY=V ...] | frame_probes regions FRAMES\n");
  return 2;
}
