// Issue 17 experiment driver (session 14): blob seeds (seed_probe.hpp) on the realistic set where the
// default profile found no tag, read as tags; how many lost tags they add, at what cost.
//   seed_blobs FRAMES MIN_RESPONSE MAX_SEEDS [K ...]   (K: the tag's side over the seed's to try)
// SEED_DEBUG=1 prints, for every lost tag, the nearest seed of all; SEED_ALL_QUADS_FREE=1 lets seeds lie
// inside quads that did not decode. Prints an experiment log, not a results/ CSV.
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "codes/families.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "realistic/realistic_run.hpp"
#include "realistic/realistic_set.hpp"
#include "seed_probe.hpp"

using namespace tagbench;
using namespace tagbench::bench;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: seed_blobs FRAMES MIN_RESPONSE MAX_SEEDS [K ...]\n");
    return 2;
  }
  const int frames = std::stoi(argv[1]);
  const DetectorOptions opt;
  const Detector det(opt);
  const TagFamily fam = load_family("36h11");
  const double min_response = std::stod(argv[2]);
  const int max_seeds = std::stoi(argv[3]);
  const std::vector<double> sides = {12, 15, 18, 22, 27, 33, 40};
  std::vector<double> factors;  // the tag's side over the seed's to try (default 1, 0.9, 1.1)
  for (int i = 4; i < argc; ++i) factors.push_back(std::stod(argv[i]));
  if (factors.empty()) factors = {1.0, 0.9, 1.1};
  std::map<std::string, std::array<int, 3>> bins;  // bin -> (tags, found by the detector, + by seeds)
  int seeds = 0, wrong = 0;
  double seed_ms = 0, decode_ms = 0, detect_ms = 0;
  for (int fi = 0; fi < frames; ++fi) {
    const RealisticFrame f = make_realistic_frame(RealisticSettings{}, fi);
    const ImageF img = to_float_image(f.image);
    DetectorTrace trace;
    auto t0 = std::chrono::steady_clock::now();
    const auto dets = det.detect(img, &trace);
    auto t1 = std::chrono::steady_clock::now();
    std::vector<Corners> covered;
    if (!std::getenv("SEED_ALL_QUADS_FREE"))  // quads found but not decoded cover their seeds too
      for (const auto& q : trace.quads) covered.push_back(q.corners);
    for (const auto& d : dets) covered.push_back(d.corners);
    const auto bs = blob_seeds(img, sides, min_response, covered, max_seeds);
    auto t2 = std::chrono::steady_clock::now();
    std::vector<Detection> more;
    for (const auto& s : bs)
      if (auto d = decode_seed(img, s, fam, opt, factors)) more.push_back(*d);
    auto t3 = std::chrono::steady_clock::now();
    detect_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
    seed_ms += std::chrono::duration<double, std::milli>(t2 - t1).count();
    decode_ms += std::chrono::duration<double, std::milli>(t3 - t2).count();
    seeds += static_cast<int>(bs.size());
    const auto near = [](const Detection& d, const RealisticTag& t) {
      return d.id == t.id && (d.center - centre_of(t.corners)).norm() < 0.5 * t.black_square_px;
    };
    std::vector<bool> matched(more.size(), false), lost(f.tags.size(), true);
    for (std::size_t ti = 0; ti < f.tags.size(); ++ti) {
      const RealisticTag& t = f.tags[ti];
      auto& b = bins[size_bin_of(t.black_square_px).name];
      ++b[0];
      bool by_seed = false;
      for (const auto& d : dets) lost[ti] = lost[ti] && !near(d, t);
      for (std::size_t k = 0; k < more.size(); ++k)
        if (near(more[k], t)) by_seed = true, matched[k] = true;
      b[1] += !lost[ti], b[2] += lost[ti] && by_seed;
    }
    for (std::size_t k = 0; k < more.size(); ++k) wrong += !matched[k];
    if (std::getenv("SEED_DEBUG")) {  // each lost tag: the nearest seed of all (uncovered, uncapped)
      const auto all = blob_seeds(img, sides, min_response, {}, 100000);
      for (std::size_t ti = 0; ti < f.tags.size(); ++ti) {
        const RealisticTag& t = f.tags[ti];
        if (!lost[ti]) continue;
        const Eigen::Vector2d c = centre_of(t.corners);
        std::size_t best = all.size();
        for (std::size_t k = 0; k < all.size(); ++k)
          if (best == all.size() || (all[k].centre - c).norm() < (all[best].centre - c).norm()) best = k;
        if (best == all.size()) continue;
        const bool cov = inside_any(covered, all[best].centre);
        const auto d = decode_seed(img, all[best], fam, opt, factors);
        std::printf("  lost px %.1f tilt %.0f: seed rank %zu of %zu off %.1f side %.0f resp %.3f%s%s\n", t.black_square_px,
                    t.tilt_deg, best, all.size(), (all[best].centre - c).norm(), all[best].side, all[best].response,
                    cov ? " covered" : "", d ? (d->id == t.id ? " DECODES" : " wrong") : "");
      }
    }
  }
  const int n = frames;  // per-frame means
  std::printf("min_response %.3f max_seeds %d: %.1f seeds a frame; detector %.1f ms, seeds %.2f ms, decoding %.2f ms a frame; "
              "%d decoded seeds match no tag\n", min_response, max_seeds, 1.0 * seeds / n, detect_ms / n, seed_ms / n,
              decode_ms / n, wrong);
  for (const auto& [b, v] : bins) std::printf("  %s: %d tags, detector %d, + seeds %d\n", b.c_str(), v[0], v[1], v[2]);
  return 0;
}
