// Issue 17 experiment driver: the threshold quad stage (detect/threshold_quads.hpp) against the
// paper's gradient quads and libapriltag 3 (d1, d2) on the same frames, single thread.
//
//   thresh_quads realistic N [FAMILY [DETECTORS]]  detection per tag size on N realistic frames (bench/realistic)
//   thresh_quads small N [FAMILY [DETECTORS]]      make_scene drawn at 5x, INTER_AREA down, noise, JPEG q75
//   thresh_quads realistic-blurS N ...             the same with every frame's defocus sigma = S px
//   thresh_quads defocusS N ...                    make_scene 640x480 (tags 38-120 px) blurred with sigma S
//     DETECTORS: comma-separated; thresh-{full,half}[-norefine][-blurS][-tileN][-contrastC][-minpixP][-dual][-paper]
//     (C on 0..255; -dual adds a half-size pass, -paper the paper's gradient quads) or a make_comparator name
//   thresh_quads speed REPS [DIR [MAX [DIR2 ...]]]  ms per image (median of REPS, detectors alternating):
//                                        synthetic scenes, realistic frames, then MAX images of each folder
//   thresh_quads natural DIR [MAX [FULL HALF]]  candidate quads and 16h5 false detections per natural image
//   thresh_quads diff DIR MAX OURS REF   OURS' misses against REF, split into candidate and decode losses
//   thresh_quads profile NAME SET [MAX]  one detector once over SET (synthetic, realistic or a folder): for
//                                        valgrind --tool=callgrind (instruction counts) or perf
// Results are printed as tables (an experiment log, not a results/ CSV). Seeds are fixed and printed.
#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "experiments/thresh_detect.hpp"
#include "experiments/thresh_quads_detail.hpp"
#include "scenes.hpp"

using namespace tagbench;
using namespace tagbench::bench;
using namespace tagbench::bench::experiments;
using namespace tagbench::bench::experiments::thresh_quads_detail;

namespace {

// The same quad up to the cyclic order of its corners: every corner within tol px.
bool same_quad(const Corners& a, const Corners& b, double tol) {
  for (std::size_t r = 0; r < 4; ++r) {
    bool ok = true;
    for (std::size_t i = 0; i < 4 && ok; ++i) ok = (a[(i + r) % 4] - b[i]).norm() <= tol;
    if (ok) return true;
  }
  return false;
}
Eigen::Vector2d centre(const Corners& c) { return 0.25 * (c[0] + c[1] + c[2] + c[3]); }

std::vector<std::unique_ptr<Comparator>> detectors(const std::string& family, const std::vector<std::string>& names,
                                                   int max_hamming = 1) {
  std::vector<std::unique_ptr<Comparator>> v;
  ComparatorSetup setup;
  setup.family = family;
  for (const auto& n : names) {
    if (n.rfind("thresh-", 0) == 0) {  // thresh-{full,half}[-norefine][-blurS]
      ThreshDetectorOptions o;
      o.family = family;
      o.max_hamming = max_hamming;
      o.quads.halve = n.find("half") != std::string::npos;
      o.quads.refine_edges = n.find("norefine") == std::string::npos;
      o.quads.fit.min_tag_width = 6;
      if (const auto b = n.find("-blur"); b != std::string::npos) o.quads.blur_sigma = std::stod(n.substr(b + 5));
      if (const auto b = n.find("-tile"); b != std::string::npos) o.quads.threshold.tile_size = std::stoi(n.substr(b + 5));
      if (const auto b = n.find("-contrast"); b != std::string::npos)
        o.quads.threshold.min_contrast = std::stof(n.substr(b + 9)) / 255.0f;
      if (const auto b = n.find("-minpix"); b != std::string::npos)
        o.quads.boundaries.min_component_pixels = static_cast<std::uint32_t>(std::stoul(n.substr(b + 7)));
      if (n.find("-dual") != std::string::npos) {  // + the same at half size
        o.second_pass = o.quads;
        o.second_pass->halve = true;
      }
      o.with_paper_quads = n.find("-paper") != std::string::npos;
      v.push_back(std::make_unique<ThreshDetector>(n, o));
    } else {
      v.push_back(make_comparator(n, setup));
    }
  }
  return v;
}

std::vector<double> kBins = {12, 16, 20, 25, 30, 40.01};
int bin_of(double px) {
  for (std::size_t i = 0; i + 1 < kBins.size(); ++i)
    if (px >= kBins[i] && px < kBins[i + 1]) return static_cast<int>(i);
  return -1;
}

void detection_table(const std::vector<Frame>& frames, const std::string& family, const std::vector<std::string>& names) {
  auto dets = detectors(family, names);
  const std::size_t nb = kBins.size() - 1;
  std::vector<std::vector<int>> hit(dets.size(), std::vector<int>(nb, 0));
  std::vector<int> total(nb, 0), wrong(dets.size(), 0), all_hits(dets.size(), 0);
  std::vector<double> ms(dets.size(), 0), rms(dets.size(), 0), quads(dets.size(), 0);
  std::vector<std::vector<int>> quad_hit(dets.size(), std::vector<int>(nb, 0));
  const std::vector<double> tilts = {0, 30, 45, 55, 66};  // tags of 20 px and more, by tilt
  std::vector<std::vector<int>> tilt_hit(dets.size(), std::vector<int>(tilts.size() - 1, 0));
  std::vector<int> tilt_total(tilts.size() - 1, 0);
  auto tilt_bin = [&](const TruthTag& t) {
    if (t.px < 20 || t.tilt < 0) return -1;
    for (std::size_t i = 0; i + 1 < tilts.size(); ++i)
      if (t.tilt >= tilts[i] && t.tilt < tilts[i + 1]) return static_cast<int>(i);
    return -1;
  };
  for (const Frame& f : frames) {
    for (const auto& t : f.tags) {
      if (bin_of(t.px) >= 0) ++total[static_cast<std::size_t>(bin_of(t.px))];
      if (tilt_bin(t) >= 0) ++tilt_total[static_cast<std::size_t>(tilt_bin(t))];
    }
    for (std::size_t d = 0; d < dets.size(); ++d) {
      const auto out = dets[d]->run(f.gray);
      ms[d] += out.ms;
      if (auto* th = dynamic_cast<ThreshDetector*>(dets[d].get())) {  // did the candidate stage find the tag at all?
        quads[d] += static_cast<double>(th->last_quads().size());
        for (const auto& t : f.tags) {
          const int b = bin_of(t.px);
          if (b < 0) continue;
          for (const Quad& q : th->last_quads())
            if (same_quad(q.corners, t.corners, std::max(1.0, 0.08 * t.px))) {
              ++quad_hit[d][static_cast<std::size_t>(b)];
              break;
            }
        }
      }
      for (const Found& x : out.found) {
        bool matched = false;
        for (const auto& t : f.tags) {
          if (t.id != x.id || (centre(x.corners) - centre(t.corners)).norm() > 0.3 * t.px) continue;
          matched = true;
          const int b = bin_of(t.px);
          if (tilt_bin(t) >= 0) ++tilt_hit[d][static_cast<std::size_t>(tilt_bin(t))];
          if (b >= 0) {  // the summary columns count the binned tags only
            ++hit[d][static_cast<std::size_t>(b)];
            ++all_hits[d];
            double e = 0;
            for (std::size_t i = 0; i < 4; ++i) e += (x.corners[i] - t.corners[i]).squaredNorm();
            rms[d] += std::sqrt(e / 4);
          }
          break;
        }
        if (!matched) ++wrong[d];
      }
    }
  }
  std::printf("%-22s", "black square px");
  for (std::size_t b = 0; b < nb; ++b) std::printf(" [%2.0f,%2.0f)", kBins[b], kBins[b + 1]);
  std::printf("    all  wrong  corner_rms  ms/frame\n%-22s", "tags");
  int sum = 0;
  for (std::size_t b = 0; b < nb; ++b) std::printf(" %7d", total[b]), sum += total[b];
  std::printf(" %6d\n", sum);
  for (std::size_t d = 0; d < dets.size(); ++d) {
    std::printf("%-22s", dets[d]->name().c_str());
    for (std::size_t b = 0; b < nb; ++b) std::printf(" %6.1f%%", total[b] ? 100.0 * hit[d][b] / total[b] : 0.0);
    std::printf(" %5.1f%% %6d %9.3f %9.2f\n", sum ? 100.0 * all_hits[d] / sum : 0.0, wrong[d],
                all_hits[d] ? rms[d] / all_hits[d] : 0.0, ms[d] / static_cast<double>(frames.size()));
  }
  if (tilt_total[0] + tilt_total.back() > 0) {
    std::printf("tags >= 20 px by tilt  ");
    for (std::size_t i = 0; i + 1 < tilts.size(); ++i) std::printf(" [%2.0f,%2.0f):%-4d", tilts[i], tilts[i + 1], tilt_total[i]);
    std::printf("\n");
    for (std::size_t d = 0; d < dets.size(); ++d) {
      std::printf("%-22s", dets[d]->name().c_str());
      for (std::size_t i = 0; i + 1 < tilts.size(); ++i)
        std::printf(" %10.1f%%", tilt_total[i] ? 100.0 * tilt_hit[d][i] / tilt_total[i] : 0.0);
      std::printf("\n");
    }
  }
  for (std::size_t d = 0; d < dets.size(); ++d) {
    if (!dynamic_cast<ThreshDetector*>(dets[d].get())) continue;
    std::printf("%-22s", (dets[d]->name() + " quad").c_str());
    int qh = 0;
    for (std::size_t b = 0; b < nb; ++b) std::printf(" %6.1f%%", total[b] ? 100.0 * quad_hit[d][b] / total[b] : 0.0), qh += quad_hit[d][b];
    std::printf(" %5.1f%%  (a candidate quad within max(1, 0.08 side) px of every corner; %.0f quads/frame)\n",
                sum ? 100.0 * qh / sum : 0.0, quads[d] / static_cast<double>(frames.size()));
  }
}

void speed_table(const std::string& label, const std::vector<cv::Mat>& images, int reps) {
  const std::vector<std::string> names = {"thresh-full", "libapriltag-d1", "thresh-half", "libapriltag-d2", "tagbench-paper",
                                          "tagbench-paper-half", "thresh-full-tile2-contrast20", "thresh-half-tile2-contrast20"};
  auto dets = detectors("36h11", names);
  std::vector<double> sum(dets.size(), 0);
  std::vector<std::size_t> found(dets.size(), 0);
  for (const cv::Mat& im : images) {
    for (auto& d : dets) d->run(im);  // warm the workspaces
    std::vector<std::vector<double>> t(dets.size());
    for (int r = 0; r < reps; ++r)
      for (std::size_t d = 0; d < dets.size(); ++d) {  // alternating
        const auto out = dets[d]->run(im);
        t[d].push_back(out.ms);
        if (r == 0) found[d] += out.found.size();
      }
    for (std::size_t d = 0; d < dets.size(); ++d) {
      std::sort(t[d].begin(), t[d].end());
      sum[d] += t[d][t[d].size() / 2];
    }
  }
  std::printf("%-28s %5zu images:", label.c_str(), images.size());
  for (std::size_t d = 0; d < dets.size(); ++d)
    std::printf("  %s %.2f ms (%zu found)", names[d].c_str(), sum[d] / images.size(), found[d]);
  std::printf("\n    ratios: thresh-full/d1 %.2f  thresh-half/d2 %.2f  tile2-c20 full/d1 %.2f  half/d2 %.2f  tagbench-full/d1 %.2f  "
              "tagbench-half/d2 %.2f\n",
              sum[0] / sum[1], sum[2] / sum[3], sum[6] / sum[1], sum[7] / sum[3], sum[4] / sum[1], sum[5] / sum[3]);
}

void natural_table(const std::vector<cv::Mat>& images, const std::string& full, const std::string& half) {
  DetectorOptions po;
  po.families = {"16h5"};
  Detector paper(po);
  DetectorWorkspace pws;
  const std::vector<std::string> names = {full, half, "libapriltag-d1", "libapriltag-d2"};
  auto h1 = detectors("16h5", names, 1);
  auto h2 = detectors("16h5", {full, half}, 2);
  double paper_quads = 0, paper_fp = 0;
  std::vector<double> quads(2, 0), fp(names.size(), 0), fp2(2, 0);
  for (const cv::Mat& im : images) {
    StageTimings tm;
    paper_fp += static_cast<double>(detect(paper, im, pws, nullptr, &tm).size());
    paper_quads += static_cast<double>(tm.quad_count);
    for (std::size_t d = 0; d < h1.size(); ++d) {
      fp[d] += static_cast<double>(h1[d]->run(im).found.size());
      if (d < 2) quads[d] += static_cast<double>(static_cast<ThreshDetector&>(*h1[d]).last_stats().quads.quads);
    }
    for (std::size_t d = 0; d < h2.size(); ++d) fp2[d] += static_cast<double>(h2[d]->run(im).found.size());
  }
  const double n = static_cast<double>(images.size());
  std::printf("%zu natural images, per image: candidate quads paper %.1f, %s %.1f, %s %.1f\n", images.size(),
              paper_quads / n, full.c_str(), quads[0] / n, half.c_str(), quads[1] / n);
  std::printf("16h5 false detections per image: paper(h1) %.2f", paper_fp / n);
  for (std::size_t d = 0; d < names.size(); ++d)
    std::printf("  %s%s %.2f", names[d].c_str(), d < 2 ? "(h1)" : "(h2)", fp[d] / n);
  std::printf("  %s(h2) %.2f  %s(h2) %.2f\n", full.c_str(), fp2[0] / n, half.c_str(), fp2[1] / n);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    cv::setNumThreads(1);
    const std::vector<std::string> a(argv + 1, argv + argc);
    if (a.size() < 2) throw std::invalid_argument("usage: thresh_quads realistic|small N [FAMILY] | speed REPS DIR | natural DIR [MAX]");
    const std::vector<std::string> all = {"thresh-full", "thresh-half", "thresh-full-norefine", "tagbench-paper",
                                          "tagbench-paper-half", "libapriltag-d1", "libapriltag-d2"};
    if (a[0].rfind("defocus", 0) == 0) {  // defocusS N [FAMILY [DETECTORS]]
      kBins = {30, 60, 90, 130};
      const double sigma = std::stod(a[0].substr(7));
      const int n = std::stoi(a[1]);
      const std::string fam = a.size() > 2 ? a[2] : "36h11";
      std::vector<std::string> names = all;
      if (a.size() > 3) {
        names.clear();
        std::size_t p = 0;
        for (std::size_t c; (c = a[3].find(',', p)) != std::string::npos; p = c + 1) names.push_back(a[3].substr(p, c - p));
        names.push_back(a[3].substr(p));
      }
      std::printf("defocus sigma %.1f px, %d make_scene 640x480 frames (seed 500+), noise 2, JPEG 90\n", sigma, n);
      detection_table(defocus_frames(n, fam, sigma), fam, names);
    } else if (a[0] == "realistic" || a[0] == "small" || a[0].rfind("realistic-blur", 0) == 0) {
      const int n = std::stoi(a[1]);
      const std::string fam = a.size() > 2 ? a[2] : "36h11";
      std::printf("%s frames: %d, family %s, seed 1\n", a[0].c_str(), n, fam.c_str());
      std::vector<std::string> names = all;
      if (a.size() > 3) {  // a comma-separated list instead
        names.clear();
        std::size_t p = 0;
        for (std::size_t c; (c = a[3].find(',', p)) != std::string::npos; p = c + 1) names.push_back(a[3].substr(p, c - p));
        names.push_back(a[3].substr(p));
      }
      const double blur = a[0].rfind("realistic-blur", 0) == 0 ? std::stod(a[0].substr(14)) : -1;
      detection_table(a[0] == "small" ? small_frames(n, fam, 1) : realistic_frames(n, fam, 1, blur), fam, names);
    } else if (a[0] == "speed") {
      const int reps = std::stoi(a[1]);
      std::vector<cv::Mat> synth, real;
      for (int i = 0; i < 6; ++i) synth.push_back(make_scene(1280, 960, "36h11", 6, 100 + static_cast<std::uint32_t>(i)).image);
      for (const auto& f : realistic_frames(10, "36h11", 1)) real.push_back(f.gray);
      speed_table("synthetic 1280x960 (seed 100+)", synth, reps);
      speed_table("realistic 800x600 (seed 1)", real, reps);
      // Further folders (natural photos, ray-traced frames, ...), MAX images of each spread over the folder.
      const std::size_t max = a.size() > 3 ? std::stoul(a[3]) : 60;
      if (a.size() > 2) speed_table("folder " + a[2], load_gray(image_files(a[2], max)), reps);
      for (std::size_t i = 4; i < a.size(); ++i) speed_table("folder " + a[i], load_gray(image_files(a[i], max)), reps);
    } else if (a[0] == "profile") {
      if (a.size() < 3) throw std::invalid_argument("usage: thresh_quads profile NAME SET [MAX]");
      std::vector<cv::Mat> images;
      if (a[2] == "synthetic")
        for (int i = 0; i < 6; ++i) images.push_back(make_scene(1280, 960, "36h11", 6, 100 + static_cast<std::uint32_t>(i)).image);
      else if (a[2] == "realistic")
        for (const auto& f : realistic_frames(10, "36h11", 1)) images.push_back(f.gray);
      else
        images = load_gray(image_files(a[2], a.size() > 3 ? std::stoul(a[3]) : 20));
      auto det = detectors("36h11", {a[1]});
      double ms = 0;
      std::size_t found = 0;
      for (const auto& im : images) {
        const auto out = det[0]->run(im);
        ms += out.ms;
        found += out.found.size();
      }
      std::printf("%s on %zu images: %zu found, %.2f ms/image\n", a[1].c_str(), images.size(), found, ms / images.size());
    } else if (a[0] == "diff") {  // diff DIR MAX OURS REF: where REF finds a tag OURS does not, was there a candidate quad?
      if (a.size() < 5) throw std::invalid_argument("usage: thresh_quads diff DIR MAX OURS REF");
      auto dets = detectors("36h11", {a[3], a[4]});
      auto& ours = dynamic_cast<ThreshDetector&>(*dets[0]);
      int missed = 0, with_quad = 0, extra = 0;
      for (const auto& file : image_files(a[1], std::stoul(a[2]))) {
        const cv::Mat im = cv::imread(file, cv::IMREAD_GRAYSCALE);
        if (im.empty()) continue;
        const auto mine = dets[0]->run(im).found;
        const auto ref = dets[1]->run(im).found;
        auto has = [](const std::vector<Found>& v, const Found& f) {
          for (const auto& g : v)
            if (g.id == f.id && (centre(g.corners) - centre(f.corners)).norm() < 3) return true;
          return false;
        };
        for (const auto& f : ref) {
          if (has(mine, f)) continue;
          ++missed;
          const double side = std::sqrt(quad_area(f.corners));
          double smin = 1e9, smax = 0;
          for (std::size_t i = 0; i < 4; ++i) {
            const double l = (f.corners[(i + 1) % 4] - f.corners[i]).norm();
            smin = std::min(smin, l), smax = std::max(smax, l);
          }
          if (std::getenv("THRESH_DIFF_VERBOSE")) std::printf("  missed: sqrt(area) %.1f px, shortest/longest side %.2f  %s\n", side, smin / smax, file.c_str());
          for (const Quad& q : ours.last_quads())
            if (same_quad(q.corners, f.corners, std::max(1.0, 0.08 * side))) {
              ++with_quad;
              break;
            }
        }
        for (const auto& f : mine) extra += !has(ref, f);
      }
      std::printf("%s misses %d of %s's detections (a candidate quad was there for %d: decode lost them); finds %d %s does not\n",
                  a[3].c_str(), missed, a[4].c_str(), with_quad, extra, a[4].c_str());
    } else if (a[0] == "natural") {
      natural_table(load_gray(image_files(a[1], a.size() > 2 ? std::stoul(a[2]) : 200)), a.size() > 3 ? a[3] : "thresh-full",
                    a.size() > 4 ? a[4] : "thresh-half");
    } else {
      throw std::invalid_argument("unknown mode '" + a[0] + "'");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "thresh_quads: %s\n", e.what());
    return 1;
  }
  return 0;
}
