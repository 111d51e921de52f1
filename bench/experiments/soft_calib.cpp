// soft_calib: the soft decoder's statistics (soft_decode.hpp) on the payloads the hard decoder
// refuses, for calibrating its acceptance rule (issue 17). Not part of make test / make bench.
//
//   soft_calib realistic --first F --frames N --out rows.csv     realistic set frames F..F+N-1 (seed 1)
//   soft_calib variants --first F --frames N --out counts.csv   area-reader variants on truth corners
//   soft_calib corpus --corpus DIR --family 36h11 [--every K] --out rows.csv
//
// realistic: every truth tag read through its TRUE corners (source "truth"), and every candidate quad
// of the default detector that no family decoded (source "quad"); corpus: every such quad of the
// default detector on every K-th image of the corpus' manifest (source "corpus", all negatives).
// A row: source, frame/image, black square px, contrast, hard decode (id or -1), the truth tag under
// the quad's centre (-1: none), soft_match's best id and rotation, D1, D2, bit errors, whether the best codeword is that tag's (right: 1, wrong: 0, no tag: -1), and
// the cells' confidences (';'-separated).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "codes/families.hpp"
#include "detect/detector.hpp"
#include "detect/homography.hpp"
#include "detect/soft_decode.hpp"
#include "realistic/realistic_set.hpp"

using namespace tagbench;
using namespace tagbench::bench;

namespace {

struct Stats {
  double px = 0, contrast = 0;
  int hard_id = -1;
  SoftMatch m;
  std::vector<float> z;
  bool ok = false;
};

Stats read_quad(const ImageF& gray, const Corners& c, const TagFamily& fam, const DetectorOptions& opt) {
  Stats s;
  const auto H = tag_homography(c);
  if (!H) return s;
  PayloadAreaOptions a = opt.payload_area;
  a.min_contrast = opt.payload.min_contrast;
  const auto r = read_payload_area(gray, *H, fam.payload_width(), a);
  if (!r) return s;
  double area = 0;
  for (int i = 0; i < 4; ++i) {
    const auto& p = c[static_cast<std::size_t>(i)];
    const auto& q = c[static_cast<std::size_t>((i + 1) % 4)];
    area += p.x() * q.y() - q.x() * p.y();
  }
  s.px = std::sqrt(std::abs(area) / 2);
  s.contrast = r->contrast * 255;
  if (const auto dec = fam.decode(r->bits, opt.bits_corrected(fam.min_hamming()))) s.hard_id = dec->id;
  s.m = soft_match(fam, r->confidence, opt.soft_decode);
  s.z = r->confidence;
  s.ok = true;
  return s;
}

bool inside(const Corners& c, const Eigen::Vector2d& p) {
  int sign = 0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = c[static_cast<std::size_t>(i)], b = c[static_cast<std::size_t>((i + 1) % 4)];
    const double cr = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
    const int s = cr > 0 ? 1 : -1;
    if (sign == 0) sign = s;
    else if (s != sign) return false;
  }
  return true;
}

void row(std::ostream& o, const std::string& source, const std::string& where, const Stats& s, int truth_id) {
  if (!s.ok || s.m.best < 0) return;
  const int id = s.m.best / 4, rot = s.m.best % 4;
  const int right = truth_id < 0 ? -1 : (id == truth_id ? 1 : 0);
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s,%s,%.2f,%.1f,%d,%d,%d,%d,%.4f,%.4f,%d,%d,%d,", source.c_str(),
                where.c_str(), s.px, s.contrast, s.hard_id, truth_id, id, rot, s.m.best_distance, s.m.second_distance,
                s.m.best_bit_errors, s.m.second_bit_errors, right);
  o << buf;
  for (std::size_t k = 0; k < s.z.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%s%.3f", k ? ";" : "", s.z[k]);
    o << buf;
  }
  o << "\n";
}

std::string arg(int argc, char** argv, const std::string& key, const std::string& def) {
  for (int i = 2; i + 1 < argc; ++i)
    if (argv[i] == "--" + key) return argv[i + 1];
  return def;
}

}  // namespace

int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: soft_calib realistic|corpus [options] --out rows.csv\n");
    return 2;
  }
  const std::string mode = argv[1];
  const std::string out = arg(argc, argv, "out", "");
  if (out.empty()) throw std::invalid_argument("--out is required");
  std::ostringstream o;
  o << "source,where,black_square_px,contrast_levels,hard_id,truth_id,best_id,best_rotation,d1,d2,e1,e2,right,z\n";
  DetectorOptions opt;
  opt.soft_decode.enabled = false;  // the hard detector's refusals
  if (mode == "realistic") {
    RealisticSettings set;
    const int first = std::stoi(arg(argc, argv, "first", "200")), frames = std::stoi(arg(argc, argv, "frames", "100"));
    const TagFamily fam = load_family(set.family);
    opt.families = {set.family};
    const Detector det(opt);
    for (int i = first; i < first + frames; ++i) {
      const RealisticFrame f = make_realistic_frame(set, i);
      const ImageF gray =
          to_float_image(ImageU8View{f.image.cols, f.image.rows, static_cast<int>(f.image.step), f.image.data});
      for (const auto& t : f.tags) {
        Stats s = read_quad(gray, t.corners, fam, opt);
        if (s.ok && s.hard_id < 0) row(o, "truth", std::to_string(i), s, t.id);
      }
      DetectorTrace tr;
      det.detect(gray, &tr);
      for (std::size_t q = 0; q < tr.quads.size() && q < tr.quad_outcomes.size(); ++q) {
        if (tr.quad_outcomes[q].fate != QuadOutcome::Fate::kNotDecoded) continue;
        const Stats s = read_quad(gray, tr.quads[q].corners, fam, opt);
        const Eigen::Vector2d c = 0.25 * (tr.quads[q].corners[0] + tr.quads[q].corners[1] + tr.quads[q].corners[2] +
                                          tr.quads[q].corners[3]);
        int truth = -1;
        for (const auto& t : f.tags)
          if (inside(t.corners, c)) truth = t.id;
        row(o, "quad", std::to_string(i), s, truth);
      }
      std::fprintf(stderr, "\rframe %d", i);
    }
  } else if (mode == "variants") {
    // Every truth tag read through its true corners by area-reader variants (sharpening x sample
    // extent): per 4 px size bin, tags read hard, read soft (hard failed), read as another id.
    RealisticSettings set;
    const int first = std::stoi(arg(argc, argv, "first", "200")), frames = std::stoi(arg(argc, argv, "frames", "100"));
    const TagFamily fam = load_family(set.family);
    struct Count { int tags = 0, hard = 0, soft = 0, wrong = 0; };
    const double sharp[] = {0.25, 0.5, 0.75}, extent[] = {0.3, 0.5};
    std::vector<std::vector<Count>> counts(6, std::vector<Count>(7));
    for (int i = first; i < first + frames; ++i) {
      const RealisticFrame f = make_realistic_frame(set, i);
      const ImageF gray =
          to_float_image(ImageU8View{f.image.cols, f.image.rows, static_cast<int>(f.image.step), f.image.data});
      for (const auto& t : f.tags) {
        const auto bin = static_cast<std::size_t>(std::clamp((static_cast<int>(t.black_square_px) - 12) / 4, 0, 6));
        const auto H = tag_homography(t.corners);
        if (!H) continue;
        for (int v = 0; v < 6; ++v) {
          PayloadAreaOptions a = opt.payload_area;
          a.min_contrast = opt.payload.min_contrast;
          a.sharpening = sharp[v / 2];
          a.small_cell_sharpening = std::max(a.small_cell_sharpening, a.sharpening);
          a.sample_extent = extent[v % 2];
          Count& c = counts[static_cast<std::size_t>(v)][bin];
          ++c.tags;
          const auto r = read_payload_area(gray, *H, fam.payload_width(), a);
          if (!r) continue;
          if (const auto dec = fam.decode(r->bits, 3)) {
            (dec->id == t.id && dec->rotation == 0 ? c.hard : c.wrong)++;
          } else if (const auto s = soft_decode(fam, *r, opt.soft_decode)) {
            (s->id == t.id && s->rotation == 0 ? c.soft : c.wrong)++;
          }
        }
      }
      std::fprintf(stderr, "\rframe %d", i);
    }
    o.str("");
    o << "sharpening,sample_extent,bin_lo_px,tags,hard,soft,wrong\n";
    for (int v = 0; v < 6; ++v)
      for (std::size_t b = 0; b < 7; ++b) {
        const Count& c = counts[static_cast<std::size_t>(v)][b];
        o << sharp[v / 2] << "," << extent[v % 2] << "," << 12 + 4 * b << "," << c.tags << "," << c.hard << ","
          << c.soft << "," << c.wrong << "\n";
      }
  } else if (mode == "corpus") {
    const std::filesystem::path dir = arg(argc, argv, "corpus", "");
    const std::string family = arg(argc, argv, "family", "36h11");
    const int every = std::stoi(arg(argc, argv, "every", "1"));
    const TagFamily fam = load_family(family);
    opt.families = {family};
    const Detector det(opt);
    std::ifstream man(dir / "manifest.tsv");
    std::string line;
    std::getline(man, line);
    int n = 0;
    while (std::getline(man, line)) {
      if (n++ % every) continue;
      const std::string file = line.substr(0, line.find('\t'));
      const cv::Mat m = cv::imread((dir / file).string(), cv::IMREAD_GRAYSCALE);
      if (m.empty()) continue;
      const ImageF gray = to_float_image(ImageU8View{m.cols, m.rows, static_cast<int>(m.step), m.data});
      DetectorTrace tr;
      det.detect(gray, &tr);
      for (std::size_t q = 0; q < tr.quads.size() && q < tr.quad_outcomes.size(); ++q)
        if (tr.quad_outcomes[q].fate == QuadOutcome::Fate::kNotDecoded)
          row(o, "corpus", file, read_quad(gray, tr.quads[q].corners, fam, opt), -1);
      std::fprintf(stderr, "\rimage %d", n);
    }
  } else {
    throw std::invalid_argument("unknown mode " + mode);
  }
  std::ofstream(out) << o.str();
  std::fprintf(stderr, "\n");
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soft_calib: %s\n", e.what());
    return 1;
  }
}
