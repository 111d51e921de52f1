#include "fp_detectors.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "codes/families.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

namespace {

struct ImageResult {
  bool readable = false;
  std::string reason;
  int width = 0, height = 0;
  std::vector<FalseDetection> detections;
  std::vector<double> ms;  // per detector x family
};

cv::Mat read_gray(const std::filesystem::path& file, std::string& reason) {
  try {
    cv::Mat m = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (m.empty()) reason = std::filesystem::exists(file) ? "OpenCV cannot decode it" : "no such file";
    return m;
  } catch (const cv::Exception& e) {
    reason = "OpenCV cannot decode it";
    return {};
  }
}

}  // namespace

FpDetectorsRun run_fp_detectors(const std::filesystem::path& dir, std::vector<corpus::CandidateImage> images,
                                const FpDetectorsOptions& options,
                                const std::function<void(const FpDetectorsProgress&)>& progress) {
  if (options.detectors.empty()) throw std::invalid_argument("no detector given");
  if (options.families.empty()) throw std::invalid_argument("no family given");
  const std::size_t pairs = options.detectors.size() * options.families.size();
  const auto external_of = [&](const std::string& name) -> const ExternalDetector* {
    for (const auto& e : options.external)
      if (e.name == name) return &e;
    return nullptr;
  };
  auto make_all = [&] {
    std::vector<std::unique_ptr<Comparator>> v;
    for (const auto& d : options.detectors)
      for (const auto& f : options.families) {
        ComparatorSetup s;
        s.family = f;
        v.push_back(external_of(d) ? nullptr : make_comparator(d, s));  // external ones run below, once
      }
    return v;
  };
  make_all();  // bad names fail here, on the calling thread, before any work
  int jobs = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  jobs = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(jobs), std::max<std::size_t>(1, images.size())));

  std::vector<ImageResult> results(images.size());
  std::atomic<std::size_t> next{0}, done{0}, found{0};
  std::mutex error_mutex;
  std::string error;
  auto work = [&] {
    try {
      const auto dets = make_all();
      for (;;) {
        const std::size_t i = next.fetch_add(1);
        if (i >= images.size()) return;
        ImageResult& r = results[i];
        const cv::Mat gray = read_gray(dir / images[i].file, r.reason);
        r.ms.assign(pairs, 0.0);
        if (!gray.empty()) {
          r.readable = true;
          r.width = gray.cols;
          r.height = gray.rows;
          for (std::size_t p = 0; p < pairs; ++p) {
            if (!dets[p]) continue;
            const DetectorOutput out = dets[p]->run(gray);
            r.ms[p] = out.ms;
            for (const Found& f : out.found) {
              FalseDetection fd;
              fd.image = static_cast<std::uint32_t>(i);
              fd.detector = options.detectors[p / options.families.size()];
              fd.family = options.families[p % options.families.size()];
              fd.id = f.id;
              fd.hamming = f.hamming;
              fd.decision_margin = f.decision_margin;
              fd.corners = f.corners;
              r.detections.push_back(std::move(fd));
            }
          }
          found += r.detections.size();
        }
        ++done;
      }
    } catch (const std::exception& e) {
      std::lock_guard lock(error_mutex);
      if (error.empty()) error = e.what();
      next = images.size();  // stop the others
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < jobs; ++t) pool.emplace_back(work);
  if (progress) {
    while (done.load() < images.size() && next.load() <= images.size()) {
      {
        std::lock_guard lock(error_mutex);
        if (!error.empty()) break;
      }
      progress({done.load(), images.size(), found.load()});
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  for (auto& t : pool) t.join();
  if (!error.empty()) throw std::runtime_error(error);
  if (progress) progress({done.load(), images.size(), found.load()});

  // The external detectors, each once on all the readable images; detections in the run's order
  // (detector, then family) within each image.
  const std::size_t nf = options.families.size();
  for (std::size_t di = 0; di < options.detectors.size(); ++di) {
    const ExternalDetector* e = external_of(options.detectors[di]);
    if (!e) continue;
    std::vector<std::string> paths;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < images.size(); ++i)
      if (results[i].readable) {
        paths.push_back(std::filesystem::absolute(dir / images[i].file).lexically_normal().string());
        which.push_back(i);
      }
    const std::vector<ImageDetections> got = paths.empty() ? std::vector<ImageDetections>{} : run_external(*e, paths);
    for (std::size_t k = 0; k < got.size(); ++k) {
      ImageResult& r = results[which[k]];
      for (std::size_t fi = 0; fi < nf; ++fi)
        if (std::isfinite(got[k].ms)) r.ms[di * nf + fi] = got[k].ms;
      for (const Found& f : got[k].found)
        for (std::size_t fi = 0; fi < nf; ++fi) {
          if (canonical_family_name(f.family) != canonical_family_name(options.families[fi])) continue;
          FalseDetection fd;
          fd.image = static_cast<std::uint32_t>(which[k]);
          fd.detector = options.detectors[di];
          fd.family = options.families[fi];
          fd.id = f.id;
          fd.hamming = f.hamming;
          fd.decision_margin = f.decision_margin;
          fd.corners = f.corners;
          r.detections.push_back(std::move(fd));
        }
    }
  }
  if (!options.external.empty()) {
    const auto rank = [&](const FalseDetection& d) {
      const auto di = std::find(options.detectors.begin(), options.detectors.end(), d.detector) - options.detectors.begin();
      const auto fi = std::find(options.families.begin(), options.families.end(), d.family) - options.families.begin();
      return std::make_pair(di, fi);
    };
    for (auto& r : results)
      std::stable_sort(r.detections.begin(), r.detections.end(),
                       [&](const FalseDetection& a, const FalseDetection& b) { return rank(a) < rank(b); });
  }

  FpDetectorsRun run;
  run.options = options;
  run.ms.assign(pairs, 0.0);
  for (std::size_t i = 0; i < images.size(); ++i) {
    ImageResult& r = results[i];
    auto& im = images[i];
    if (r.readable) {
      im.width = r.width;
      im.height = r.height;
      im.status = "ok";
      im.reason.clear();
    } else {
      im.status = "unreadable";
      im.reason = r.reason;
    }
    for (std::size_t p = 0; p < pairs; ++p) run.ms[p] += r.ms[p];
    for (auto& d : r.detections) run.detections.push_back(std::move(d));
  }
  run.images = std::move(images);
  return run;
}

std::vector<FpDetectorRow> fp_detector_rows(const FpDetectorsRun& run) {
  std::set<std::string> groups;
  for (const auto& im : run.images)
    if (im.status == "ok") groups.insert(im.group);
  std::vector<std::string> subsets{"all", "still", "video-frame"};
  for (const auto& g : groups) subsets.push_back("group:" + g);
  auto in_subset = [](const corpus::CandidateImage& im, const std::string& s) {
    if (s == "all") return true;
    if (s.rfind("group:", 0) == 0) return im.group == s.substr(6);
    return im.kind == s;
  };
  const auto& o = run.options;
  std::vector<FpDetectorRow> rows;
  for (std::size_t di = 0; di < o.detectors.size(); ++di)
    for (std::size_t fi = 0; fi < o.families.size(); ++fi) {
      // Detections per image for this detector and family.
      std::map<std::uint32_t, std::uint64_t> per_image;
      for (const auto& d : run.detections)
        if (d.detector == o.detectors[di] && d.family == o.families[fi]) ++per_image[d.image];
      for (const auto& s : subsets) {
        FpDetectorRow r;
        r.detector = o.detectors[di];
        r.family = o.families[fi];
        r.subset = s;
        for (std::size_t i = 0; i < run.images.size(); ++i) {
          const auto& im = run.images[i];
          if (im.status != "ok" || !in_subset(im, s)) continue;
          ++r.images;
          r.megapixels += static_cast<double>(im.width) * im.height / 1e6;
          const auto it = per_image.find(static_cast<std::uint32_t>(i));
          if (it != per_image.end()) {
            r.detections += it->second;
            ++r.images_with_detections;
          }
        }
        if (r.images == 0) continue;
        const double n = static_cast<double>(r.images);
        r.per_image = static_cast<double>(r.detections) / n;
        r.per_megapixel = static_cast<double>(r.detections) / r.megapixels;
        r.image_share = static_cast<double>(r.images_with_detections) / n;
        r.per_image_ci = poisson_interval(r.detections, n);
        r.per_megapixel_ci = poisson_interval(r.detections, r.megapixels);
        r.image_share_ci = wilson_interval(r.images_with_detections, r.images);
        if (s == "all") {
          const double ms = run.ms[di * o.families.size() + fi];
          r.ms_per_image = ms / n;
          r.megapixels_per_second = ms > 0 ? r.megapixels / (ms / 1000) : 0;
        }
        rows.push_back(std::move(r));
      }
    }
  return rows;
}

std::string fp_detectors_csv(const std::vector<FpDetectorRow>& rows) {
  std::ostringstream o;
  o.precision(6);
  o << "detector,family,subset,images,megapixels,detections,images_with_detections,per_image,per_image_ci95_lo,"
       "per_image_ci95_hi,per_megapixel,per_megapixel_ci95_lo,per_megapixel_ci95_hi,image_share,image_share_ci95_lo,"
       "image_share_ci95_hi,ms_per_image,megapixels_per_second\n";
  for (const auto& r : rows)
    o << r.detector << ',' << csv_field(r.family) << ',' << r.subset << ',' << r.images << ',' << r.megapixels << ','
      << r.detections << ',' << r.images_with_detections << ',' << r.per_image << ',' << r.per_image_ci.lo << ','
      << r.per_image_ci.hi << ',' << r.per_megapixel << ',' << r.per_megapixel_ci.lo << ',' << r.per_megapixel_ci.hi
      << ',' << r.image_share << ',' << r.image_share_ci.lo << ',' << r.image_share_ci.hi << ',' << r.ms_per_image
      << ',' << r.megapixels_per_second << '\n';
  return o.str();
}

namespace {
std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}
}  // namespace

std::string fp_detections_csv(const FpDetectorsRun& run) {
  std::ostringstream o;
  o.precision(7);
  o << "file,group,kind,detector,family,id,hamming,x0,y0,x1,y1,x2,y2,x3,y3,decision_margin\n";
  for (const auto& d : run.detections) {
    const auto& im = run.images[d.image];
    o << quoted(im.file) << ',' << quoted(im.group) << ',' << im.kind << ',' << d.detector << ',' << csv_field(d.family) << ','
      << d.id << ',' << d.hamming;
    for (const auto& c : d.corners) o << ',' << c.x() << ',' << c.y();
    o << ',';
    if (!std::isnan(d.decision_margin)) o << d.decision_margin;
    o << '\n';
  }
  return o.str();
}

}  // namespace tagbench::bench
