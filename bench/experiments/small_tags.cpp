// small_tags: where small tags are lost, and what the beyond-the-paper units recover (issue 17).
//
//   small_tags --source realistic|distance|blur [--count N] [--seed S] [--steps a,b,...]
//              [--cache DIR] [--processes P] [--variant SPEC]... [--no-libapriltag] [--out rows.csv]
//
// Every variant (small_tag_pipeline.hpp; SPEC "name:key=value,...", default the paper's detector
// alone) and libapriltag d1 run on the same frames. Per tag, ours is attributed: detected; no quad
// near the tag (no quad within half a side of its centre whose corners are within max(1.5 px, 20 % of
// a side) of the truth); unreadable (the quad failed the border checks); misread by k bits (k the
// distance with rotations between the reading and the code); and "oracle", the bits wrong when the
// payload is read through the TRUE corners (what the payload stage loses with perfect geometry).
// Wrong ids: detections not within half a side of a tag with that id. Prints per-size tables; the
// rows (a tag x detector per row, settings in the leading columns) go to --out.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "codes/families.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/image.hpp"
#include "experiments/small_tag_frames.hpp"
#include "experiments/small_tag_pipeline.hpp"
#include "raytrace/comparators.hpp"

using namespace tagbench;
using namespace tagbench::bench;
using namespace tagbench::bench::experiments;

namespace {

struct Row {
  std::size_t frame = 0, tag = 0;
  std::string detector, outcome;  // detected | no_quad | unreadable | misread | missed (libapriltag)
  int bits_wrong = -1, oracle_bits = -1;
  double quad_rms = -1, corner_rms = -1;
};

Eigen::Vector2d centre_of(const Corners& c) { return 0.25 * (c[0] + c[1] + c[2] + c[3]); }

double rms(const Corners& a, const Corners& b, int rot = 0) {
  double s = 0;
  for (std::size_t i = 0; i < 4; ++i) s += (a[(i + static_cast<std::size_t>(rot)) % 4] - b[i]).squaredNorm();
  return std::sqrt(s / 4);
}

bool matches(const TruthTag& t, int id, const Eigen::Vector2d& c) {
  return id == t.id && (c - centre_of(t.corners)).norm() < 0.5 * t.black_square_px;
}

const std::vector<double> kBins = {0, 10, 12, 14, 17, 20, 25, 30, 40, 1e9};
std::string bin_name(std::size_t b) {
  if (b + 2 == kBins.size()) return ">=40";
  return std::to_string(static_cast<int>(kBins[b])) + "-" + std::to_string(static_cast<int>(kBins[b + 1]));
}
std::size_t bin_of(double px) {
  for (std::size_t b = 0; b + 1 < kBins.size(); ++b)
    if (px < kBins[b + 1]) return b;
  return kBins.size() - 2;
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string x;
  while (std::getline(ss, x, ',')) v.push_back(std::stod(x));
  return v;
}

}  // namespace

int main(int argc, char** argv) try {
  FrameSource src;
  src.cache = "build/raytrace-cache";
  std::vector<Variant> variants;
  bool libapriltag = true;
  std::string out_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + ": missing value");
      return argv[++i];
    };
    if (a == "--source") src.kind = next();
    else if (a == "--count") src.count = std::stoi(next());
    else if (a == "--seed") src.seed = std::stoull(next());
    else if (a == "--steps") src.steps = parse_list(next());
    else if (a == "--cache") src.cache = next();
    else if (a == "--processes") src.processes = std::stoi(next());
    else if (a == "--variant") variants.push_back(parse_variant(next()));
    else if (a == "--no-libapriltag") libapriltag = false;
    else if (a == "--out") out_path = next();
    else throw std::invalid_argument("unknown option '" + a + "'");
  }
  if (variants.empty()) variants.push_back(Variant{});
  const TagFamily& fam = builtin_family("36h11");
  const int d = fam.payload_width();
  const std::vector<TruthFrame> frames = make_frames(src);

  std::vector<Row> rows;
  std::vector<std::string> names;
  std::map<std::string, int> wrong_ids;
  for (const auto& v : variants) names.push_back(v.name);
  std::unique_ptr<Comparator> lib;
  if (libapriltag) {
    names.push_back("libapriltag-d1");
    lib = make_comparator("libapriltag-d1", ComparatorSetup{});
  }
  for (std::size_t fi = 0; fi < frames.size(); ++fi) {
    const TruthFrame& f = frames[fi];
    const ImageF gray = to_float_image(f.gray8);
    for (const auto& v : variants) {
      const PipelineResult res = run_pipeline(gray, fam, v);
      for (const auto& det : res.detections) {
        bool ok = false;
        for (const auto& t : f.tags) ok = ok || matches(t, det.id, det.center);
        if (!ok) ++wrong_ids[v.name];
      }
      for (std::size_t ti = 0; ti < f.tags.size(); ++ti) {
        const TruthTag& t = f.tags[ti];
        Row r{fi, ti, v.name, "", -1, -1, -1, -1};
        const Code code = fam.codes()[static_cast<std::size_t>(t.id)];
        if (const auto o = read_with(gray, t.corners, d, v)) r.oracle_bits = hamming(o->bits, code);
        for (const auto& det : res.detections)
          if (matches(t, det.id, det.center)) {
            r.outcome = "detected";
            r.corner_rms = rms(det.corners, t.corners);
          }
        const experiments::QuadOutcome* best = nullptr;
        double best_rms = std::max(1.5, 0.2 * t.black_square_px);
        for (const auto& q : res.quads) {
          if ((centre_of(q.used) - centre_of(t.corners)).norm() > 0.5 * t.black_square_px) continue;
          for (int rot = 0; rot < 4; ++rot) {
            const double e = rms(q.used, t.corners, rot);
            if (e < best_rms) {
              best_rms = e;
              best = &q;
            }
          }
        }
        if (best) r.quad_rms = best_rms;
        if (r.outcome.empty()) {
          if (!best) r.outcome = "no_quad";
          else if (!best->reading) r.outcome = "unreadable";
          else {
            r.outcome = "misread";
            r.bits_wrong = hamming_with_rotations(best->reading->bits, code, d);
          }
        }
        rows.push_back(r);
      }
    }
    if (lib) {
      const DetectorOutput o = lib->run(f.gray8);
      for (const auto& det : o.found) {
        bool ok = false;
        for (const auto& t : f.tags) ok = ok || matches(t, det.id, centre_of(det.corners));
        if (!ok) ++wrong_ids["libapriltag-d1"];
      }
      for (std::size_t ti = 0; ti < f.tags.size(); ++ti) {
        Row r{fi, ti, "libapriltag-d1", "missed", -1, -1, -1, -1};
        for (const auto& det : o.found)
          if (matches(f.tags[ti], det.id, centre_of(det.corners))) {
            r.outcome = "detected";
            r.corner_rms = rms(det.corners, f.tags[ti].corners);
          }
        rows.push_back(r);
      }
    }
  }

  // Per size bin: detection rate of each detector; ours' losses by kind.
  std::printf("source %s, %zu frames, seed %llu\n", src.kind.c_str(), frames.size(),
              static_cast<unsigned long long>(src.seed));
  std::printf("%-8s %5s", "px", "tags");
  for (const auto& n : names) std::printf(" %14.14s", n.c_str());
  std::printf("\n");
  const std::size_t nb = kBins.size() - 1;
  auto tag_of = [&](const Row& r) -> const TruthTag& { return frames[r.frame].tags[r.tag]; };
  for (std::size_t b = 0; b <= nb; ++b) {  // b == nb: all
    int total = 0;
    std::vector<int> det(names.size(), 0);
    for (const auto& r : rows) {
      if (b < nb && bin_of(tag_of(r).black_square_px) != b) continue;
      const auto k = static_cast<std::size_t>(std::find(names.begin(), names.end(), r.detector) - names.begin());
      if (k == 0) ++total;
      det[k] += r.outcome == "detected";
    }
    if (total == 0) continue;
    std::printf("%-8s %5d", b < nb ? bin_name(b).c_str() : "all", total);
    for (const int x : det) std::printf(" %13.1f%%", 100.0 * x / total);
    std::printf("\n");
  }
  std::printf("wrong ids:");
  for (const auto& n : names) std::printf(" %s %d;", n.c_str(), wrong_ids[n]);
  std::printf("\n");
  for (const auto& v : variants) {
    std::printf("losses of %s (per bin: no_quad / unreadable / misread 1,2,3,4+ bits; oracle>0 = truth corners misread; median corner rms of detected)\n",
                v.name.c_str());
    for (std::size_t b = 0; b <= nb; ++b) {
      int n = 0, noq = 0, unr = 0, mis[5] = {0}, orc = 0;
      std::vector<double> crms;
      for (const auto& r : rows) {
        if (r.detector != v.name || (b < nb && bin_of(tag_of(r).black_square_px) != b)) continue;
        ++n;
        noq += r.outcome == "no_quad";
        unr += r.outcome == "unreadable";
        if (r.outcome == "misread") ++mis[std::min(r.bits_wrong, 4)];
        orc += r.oracle_bits != 0;
        if (r.corner_rms >= 0) crms.push_back(r.corner_rms);
      }
      if (n == 0) continue;
      std::sort(crms.begin(), crms.end());
      std::printf("  %-8s n %4d  no_quad %4d  unreadable %3d  misread %3d/%3d/%3d/%3d (0 bits %d)  oracle>0 %4d  rms %.3f\n",
                  b < nb ? bin_name(b).c_str() : "all", n, noq, unr, mis[1], mis[2], mis[3], mis[4], mis[0], orc,
                  crms.empty() ? -1.0 : crms[crms.size() / 2]);
    }
  }
  if (!out_path.empty()) {
    const std::filesystem::path tmp = out_path + ".tmp";
    {
      std::ofstream os(tmp);
      os << "source,seed,frame,label,condition,tag,id,black_square_px,tilt_deg,detector,outcome,bits_wrong,"
            "oracle_bits_wrong,quad_rms_px,corner_rms_px\n";
      for (const auto& r : rows) {
        const TruthFrame& f = frames[r.frame];
        const TruthTag& t = f.tags[r.tag];
        os << src.kind << ',' << src.seed << ',' << r.frame << ',' << f.label << ',' << f.condition << ',' << r.tag << ','
           << t.id << ',' << t.black_square_px << ',' << t.tilt_deg << ',' << r.detector << ',' << r.outcome << ','
           << r.bits_wrong << ',' << r.oracle_bits << ',' << r.quad_rms << ',' << r.corner_rms << '\n';
      }
      if (!os) throw std::runtime_error(out_path + ": write failed");
    }
    std::filesystem::rename(tmp, out_path);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "small_tags: %s\n", e.what());
  return 1;
}
