// The sweep's external detectors (sweep_external.hpp).
#include "raytrace/sweep_external.hpp"

#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace tagbench::bench::sweep_detail {

std::vector<std::vector<DetectorOutput>> run_external_detectors(const SweepSettings& s,
                                                                const std::vector<SweepFrame>& frames,
                                                                const RenderReport& report) {
  std::vector<std::vector<DetectorOutput>> out(s.external.size(), std::vector<DetectorOutput>(frames.size()));
  if (s.external.empty()) return out;
  const ExternalWorkDir dir;
  // The images, each distinct one written once (an unmodified frame shares its render's image).
  std::vector<std::string> images;
  std::vector<std::size_t> image_of(frames.size(), 0);
  std::map<std::string, std::size_t> by_render;
  std::string gray_path;
  cv::Mat gray;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!report.frames[i].ok()) continue;
    const SweepFrame& f = frames[i];
    const std::string png = report.frames[i].png.string();
    const bool unmodified = frame_unmodified(f);
    if (unmodified) {
      if (auto it = by_render.find(png); it != by_render.end()) {
        image_of[i] = it->second;
        continue;
      }
    }
    if (png != gray_path) {
      gray = read_frame_gray(png);
      gray_path = png;
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.png", i);
    const std::filesystem::path file = dir.path() / name;
    if (!cv::imwrite(file.string(), apply_effect(gray, f)))
      throw std::runtime_error("cannot write " + file.string() + " for the external detectors");
    image_of[i] = images.size();
    if (unmodified) by_render.emplace(png, images.size());
    images.push_back(file.string());
  }
  for (std::size_t e = 0; e < s.external.size(); ++e) {
    const std::vector<ImageDetections> got = run_external(s.external[e], images, dir.path());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (!report.frames[i].ok()) continue;
      const ImageDetections& d = got[image_of[i]];
      out[e][i].found = d.found;
      out[e][i].ms = d.ms;
    }
  }
  return out;
}

}  // namespace tagbench::bench::sweep_detail
