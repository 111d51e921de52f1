#include "speed/speed_sets.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "candidates.hpp"
#include "raytrace/comparators.hpp"
#include "realistic/realistic_set.hpp"
#include "scenes.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {
namespace fs = std::filesystem;

namespace {

cv::Mat read_gray(const fs::path& file) {
  try {
    return cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    return {};  // unreadable: the row says so
  }
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// The t distribution's 97.5 % quantile for `df` degrees of freedom (the normal's beyond 30).
double t975(std::size_t df) {
  static constexpr double kTable[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                      2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
                                      2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (df == 0) return NAN;
  return df <= 30 ? kTable[df - 1] : 1.959963984540054;
}

std::string num(double v) { return format_cell(v, "%.6g"); }

}  // namespace

ImageSet corpus_set(const fs::path& corpus_dir) {
  auto images = std::make_shared<std::vector<corpus::CandidateImage>>(corpus::corpus_images(corpus_dir));
  ImageSet s;
  s.name = "corpus";
  s.source = "natural-image corpus " + corpus_dir.string();
  s.size = images->size();
  s.image = [images, corpus_dir](std::size_t i) {
    const auto& row = images->at(i);
    return SpeedImage{row.file, row.status == "ok" ? read_gray(corpus_dir / row.file) : cv::Mat()};
  };
  return s;
}

ImageSet raytrace_cache_set(const fs::path& cache_dir) {
  if (!fs::is_directory(cache_dir)) throw std::invalid_argument(cache_dir.string() + ": no such folder");
  auto files = std::make_shared<std::vector<fs::path>>();
  for (const auto& e : fs::directory_iterator(cache_dir)) {
    const std::string n = e.path().filename().string();
    if (e.is_regular_file() && n.starts_with("frame-") && n.ends_with(".png")) files->push_back(e.path());
  }
  std::sort(files->begin(), files->end());
  ImageSet s;
  s.name = "raytrace";
  s.input_gamma = 1;  // POV-Ray's frames are linear
  s.source = "ray-traced frames in " + cache_dir.string();
  s.size = files->size();
  s.image = [files](std::size_t i) {
    const fs::path& f = files->at(i);
    return SpeedImage{f.filename().string(), read_gray(f)};
  };
  return s;
}

ImageSet spread_subset(ImageSet set, std::size_t max_images) {
  if (max_images == 0 || set.size <= max_images) return set;
  const std::size_t n = set.size;
  set.source += " (" + std::to_string(max_images) + " of " + std::to_string(n) + " images, evenly spread)";
  set.image = [inner = std::move(set.image), n, max_images](std::size_t i) { return inner(i * n / max_images); };
  set.size = max_images;
  return set;
}

ImageSet realistic_set(int frames, std::uint64_t seed, const std::string& family) {
  if (frames < 1) throw std::invalid_argument("realistic frames must be >= 1");
  RealisticSettings settings;
  settings.seed = seed;
  settings.family = family;
  ImageSet s;
  s.name = "realistic";
  s.source = "make_realistic_frame(seed " + std::to_string(seed) + ", " + family + ", frames 0.." +
             std::to_string(frames - 1) + ")";
  s.size = static_cast<std::size_t>(frames);
  s.image = [settings](std::size_t i) {
    return SpeedImage{"realistic frame " + std::to_string(i), make_realistic_frame(settings, static_cast<int>(i)).image};
  };
  return s;
}

ImageSet scene_set(const std::vector<std::pair<int, int>>& sizes, int per_size, const std::string& family) {
  if (per_size < 1) throw std::invalid_argument("scenes per size must be >= 1");
  ImageSet s;
  s.name = "scenes";
  s.input_gamma = 1;  // drawn linear (bench/scenes.hpp)
  s.source = "make_scene(6 tags of " + family + ", seeds 1.." + std::to_string(per_size) + ")";
  s.size = sizes.size() * static_cast<std::size_t>(per_size);
  s.image = [sizes, per_size, family](std::size_t i) {
    const auto [w, h] = sizes.at(i / static_cast<std::size_t>(per_size));
    const auto seed = static_cast<std::uint32_t>(i % static_cast<std::size_t>(per_size) + 1);
    return SpeedImage{"scene " + std::to_string(w) + "x" + std::to_string(h) + " seed " + std::to_string(seed),
                      make_scene(w, h, family, 6, seed).image};
  };
  return s;
}

std::vector<SpeedRow> time_image_set(const ImageSet& set, const SpeedOptions& options,
                                     const std::function<void(const SpeedProgress&)>& progress) {
  if (options.detectors.empty()) throw std::invalid_argument("no detector given");
  if (options.repeats < 1) throw std::invalid_argument("repeats must be >= 1");
  std::vector<std::unique_ptr<Comparator>> dets;
  ComparatorSetup setup;
  setup.family = options.family;
  setup.input_gamma = set.input_gamma;
  for (const auto& name : options.detectors) dets.push_back(make_comparator(name, setup));

  std::vector<SpeedRow> rows;
  const std::size_t nd = dets.size();
  for (std::size_t i = 0; i < set.size; ++i) {
    const SpeedImage img = set.image(i);
    std::vector<SpeedRow> here(nd);
    for (std::size_t k = 0; k < nd; ++k) {
      here[k] = SpeedRow{set.name, img.name, options.detectors[k], i, img.gray8.cols, img.gray8.rows,
                         !img.gray8.empty(), 0, 0};
    }
    if (!img.gray8.empty()) {
      std::vector<double> best(nd, INFINITY);
      for (int r = 0; r < options.repeats; ++r)
        for (std::size_t j = 0; j < nd; ++j) {
          const std::size_t k = (i + j) % nd;  // rotate who goes first
          const DetectorOutput out = dets[k]->run(img.gray8);
          best[k] = std::min(best[k], out.ms);
          here[k].found = out.found.size();
        }
      for (std::size_t k = 0; k < nd; ++k) here[k].ms = best[k];
    }
    rows.insert(rows.end(), here.begin(), here.end());
    if (progress) progress({set.name, i + 1, set.size});
  }
  return rows;
}

std::vector<SpeedSummary> summarise_speed(const std::vector<SpeedRow>& rows) {
  std::vector<SpeedSummary> out;
  std::map<std::pair<std::string, std::string>, std::size_t> at;  // (set, detector) -> index in out
  std::vector<std::vector<double>> times;
  for (const SpeedRow& r : rows) {
    const auto key = std::make_pair(r.set, r.detector);
    auto it = at.find(key);
    if (it == at.end()) {
      it = at.emplace(key, out.size()).first;
      out.push_back(SpeedSummary{r.set, r.detector});
      times.emplace_back();
    }
    if (!r.readable) continue;
    SpeedSummary& s = out[it->second];
    ++s.images;
    s.megapixels += static_cast<double>(r.width) * r.height / 1e6;
    s.total_ms += r.ms;
    s.found += r.found;
    times[it->second].push_back(r.ms);
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].median_ms = median_of(times[i]);
    out[i].mpx_per_s = out[i].total_ms > 0 ? out[i].megapixels / (out[i].total_ms / 1000) : 0;
  }
  return out;
}

std::vector<SpeedRatio> speed_ratios(const std::vector<SpeedRow>& rows,
                                     const std::vector<std::pair<std::string, std::string>>& pairs) {
  // set -> image index -> detector -> ms
  std::map<std::string, std::map<std::size_t, std::map<std::string, double>>> by_set;
  std::vector<std::string> set_order;
  for (const SpeedRow& r : rows) {
    if (!by_set.count(r.set)) set_order.push_back(r.set);
    auto& images = by_set[r.set];
    if (r.readable) images[r.index][r.detector] = r.ms;
  }
  std::vector<SpeedRatio> out;
  for (const auto& set : set_order)
    for (const auto& [det, peer] : pairs) {
      std::vector<double> logs, ratios;
      for (const auto& [index, img] : by_set[set]) {
        const auto a = img.find(det), b = img.find(peer);
        if (a == img.end() || b == img.end() || !(a->second > 0) || !(b->second > 0)) continue;
        ratios.push_back(a->second / b->second);
        logs.push_back(std::log(a->second / b->second));
      }
      if (logs.empty()) continue;
      SpeedRatio q{set, det, peer, logs.size()};
      double mean = 0;
      for (const double l : logs) mean += l;
      mean /= static_cast<double>(logs.size());
      double var = 0;
      for (const double l : logs) var += (l - mean) * (l - mean);
      q.geometric_mean = std::exp(mean);
      if (logs.size() > 1) {
        const double se = std::sqrt(var / static_cast<double>(logs.size() - 1) / static_cast<double>(logs.size()));
        q.ci_lo = std::exp(mean - t975(logs.size() - 1) * se);
        q.ci_hi = std::exp(mean + t975(logs.size() - 1) * se);
      } else {
        q.ci_lo = q.ci_hi = q.geometric_mean;
      }
      q.median = median_of(ratios);
      q.share_faster = static_cast<double>(std::count_if(ratios.begin(), ratios.end(), [](double r) { return r < 1; })) /
                       static_cast<double>(ratios.size());
      out.push_back(q);
    }
  return out;
}

std::string speed_rows_csv(const std::vector<SpeedRow>& rows, const std::string& settings) {
  std::ostringstream s;
  s << "set,index,image,width,height,detector,readable,ms,found,settings\n";
  for (const SpeedRow& r : rows)
    s << r.set << ',' << r.index << ',' << csv_field(r.image) << ',' << r.width << ',' << r.height << ',' << r.detector << ','
      << (r.readable ? 1 : 0) << ',' << (r.readable ? num(r.ms) : "") << ',' << r.found << ',' << csv_field(settings)
      << '\n';
  return s.str();
}

std::string speed_summary_csv(const std::vector<SpeedSummary>& summary, const std::vector<SpeedRatio>& ratios,
                              const std::string& settings) {
  std::ostringstream s;
  s << "set,detector,images,megapixels,total_ms,median_ms,mpx_per_s,found,ratio_peer,ratio_geomean,ratio_ci_lo,"
       "ratio_ci_hi,ratio_median,share_faster,settings\n";
  for (const SpeedSummary& m : summary) {
    s << m.set << ',' << m.detector << ',' << m.images << ',' << num(m.megapixels) << ',' << num(m.total_ms) << ','
      << num(m.median_ms) << ',' << num(m.mpx_per_s) << ',' << m.found << ',';
    const auto q = std::find_if(ratios.begin(), ratios.end(),
                                [&](const SpeedRatio& r) { return r.set == m.set && r.detector == m.detector; });
    if (q != ratios.end())
      s << q->peer << ',' << num(q->geometric_mean) << ',' << num(q->ci_lo) << ',' << num(q->ci_hi) << ','
        << num(q->median) << ',' << num(q->share_faster) << ',';
    else
      s << ",,,,,,";
    s << csv_field(settings) << '\n';
  }
  return s.str();
}

}  // namespace tagbench::bench
