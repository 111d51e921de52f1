// Candidate extraction: the detector up to its quad search on every image, then each quad's payload read
// at d = 4, 5, 6 (the store, its index, shards and scoring are in candidate_store.cpp,
// candidate_shards.cpp, candidate_score.cpp).
#include "candidates.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "detect/detector_opencv.hpp"
#include "detect/find_quads_in_image.hpp"
#include "detect/homography.hpp"
#include "detect/payload_decode.hpp"
#include "scan.hpp"
#include "sources.hpp"
#include "tools/atomic_file.hpp"

namespace fs = std::filesystem;

namespace tagbench::corpus {
namespace {

const char* rule_name(CloseEnoughRule r) {
  switch (r) {
    case CloseEnoughRule::kPaper2011: return "paper2011";
    case CloseEnoughRule::kCode2010: return "code2010";
    case CloseEnoughRule::kCode2012: return "code2012";
  }
  return "?";
}

}  // namespace

std::vector<CandidateRecord> image_candidates(const ImageF& gray, std::uint32_t image_id, const DetectorOptions& opt,
                                              std::size_t* quad_count) {
  if (gray.empty()) throw std::invalid_argument("empty image");
  if (static_cast<long long>(gray.width) * gray.height > opt.max_pixels)
    throw std::invalid_argument("image " + std::to_string(gray.width) + "x" + std::to_string(gray.height) +
                                " is over the memory limit of " + std::to_string(opt.max_pixels) + " pixels");
  // The detector's stages 1-5, the same function Detector::detect calls.
  DetectorWorkspace workspace;
  const FoundQuads found = find_quads_in_image(gray, opt, workspace);
  const std::vector<Quad>& quads = found.quads;
  const ImageF& decode_image = *found.decode_image;
  if (quad_count) *quad_count = quads.size();

  // The detector's border pre-filter (PayloadOptions::quick_reject) is NOT applied here: the
  // paper's false-positive measurement counts every candidate quad whose payload can be read, so
  // every quad goes to read_payload. read_payload itself still refuses a quad whose cells leave
  // the image or whose border gives no usable (contrasting) model.
  const PayloadOptions& payload = opt.payload;
  std::vector<CandidateRecord> out;
  out.reserve(quads.size() * kCandidateWidths.size());
  for (const Quad& q : quads) {
    const auto H = tag_homography(q.corners);
    if (!H) continue;
    CandidateRecord r;
    r.image = image_id;
    for (std::size_t i = 0; i < 4; ++i)
      r.corners[i] = {static_cast<float>(q.corners[i].x()), static_cast<float>(q.corners[i].y())};
    for (const int d : kCandidateWidths) {
      const auto reading = read_payload(decode_image, *H, d, payload, false);
      if (!reading) continue;
      r.d = static_cast<std::uint8_t>(d);
      r.bits = reading->bits;
      r.margin = static_cast<float>(reading->margin);
      out.push_back(r);
    }
  }
  return out;
}

std::string candidate_settings(const DetectorOptions& o) {
  std::ostringstream s;
  s.precision(17);
  s << "stages=blur,gradient,segmentation,line_fit,quad_search,read_payload(no quick_reject)\n"
    << "widths=4,5,6\n"
    << "seg_sigma=" << o.seg_sigma << "\n"
    << "decode_sigma=" << o.decode_sigma << "\n"
    << "half_resolution=" << (o.half_resolution ? 1 : 0) << "\n"
    << "min_mag=" << o.segmentation.min_mag << "\n"
    << "max_edge_cost=" << o.segmentation.max_edge_cost << "\n"
    << "weight_scale=" << o.segmentation.weight_scale << "\n"
    << "k_theta=" << o.segmentation.k_theta << "\n"
    << "k_mag=" << o.segmentation.k_mag << "\n"
    << "min_cluster_size=" << o.segmentation.min_cluster_size << "\n"
    << "min_length=" << o.line_fit.min_length << "\n"
    << "close_enough=" << rule_name(o.quad_search.close_enough) << "\n"
    << "min_tag_size=" << o.quad_search.min_tag_size << "\n"
    << "max_aspect=" << o.quad_search.max_aspect << "\n"
    << "winding=" << o.quad_search.winding_min << "," << o.quad_search.winding_max << "\n"
    << "grid_cell=" << o.quad_search.grid_cell << "\n"
    << "max_quads=" << o.quad_search.max_quads << "\n"
    << "segments_on_sides=" << (o.quad_search.segments_on_sides ? 1 : 0) << "\n"
    << "min_contrast=" << o.payload.min_contrast << "\n";
  return s.str();
}

std::vector<CandidateImage> corpus_images(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": no such directory");
  std::vector<CandidateImage> out;
  const fs::path manifest = dir / "manifest.tsv";
  if (fs::exists(manifest)) {
    for (const auto& row : parse_manifest(read_file(manifest), manifest.string())) {
      CandidateImage i;
      i.file = row.file;
      i.group = row.group;
      i.kind = row.kind;
      out.push_back(std::move(i));
    }
    return out;
  }
  // Listed, not decoded: the extraction decodes each image anyway (and records its size), and every
  // shard lists the whole folder, so a decoding scan would cost each shard as much as the work.
  const FolderScan scan = list_image_files(dir);
  for (const auto& s : scan.images) {
    CandidateImage i;
    i.file = fs::relative(s.file, dir).generic_string();
    i.kind = "still";
    out.push_back(std::move(i));
  }
  for (const auto& u : scan.unreadable) {  // listed, so the index accounts for every file
    CandidateImage i;
    i.file = fs::relative(u.file, dir).generic_string();
    i.kind = "still";
    i.status = "unreadable";
    i.reason = u.reason;
    out.push_back(std::move(i));
  }
  // Files named corpus_candidates* at the top are this program's own (the default stores and their
  // temporaries). Shards running at once into the folder would otherwise list a temporary that has
  // vanished by the time it is opened as an unreadable row the other shards lack.
  std::erase_if(out, [](const CandidateImage& i) {
    return i.file.find('/') == std::string::npos && i.file.rfind("corpus_candidates", 0) == 0;
  });
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.file < b.file; });
  return out;
}

CandidateStore extract_candidates(const fs::path& dir, std::vector<CandidateImage> images, const DetectorOptions& opt,
                                  int jobs, const std::function<void(const ExtractProgress&)>& progress) {
  if (images.size() > std::numeric_limits<std::uint32_t>::max()) throw std::runtime_error("too many images");
  CandidateStore store;
  store.settings = candidate_settings(opt);
  const std::size_t n = images.size();
  std::vector<std::vector<CandidateRecord>> per(n);
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex mu;
  std::condition_variable wake;
  std::atomic<std::uint64_t> quads{0};
  auto work = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      CandidateImage& im = images[i];
      if (im.status == "ok") {
        try {
          const cv::Mat m = cv::imread((dir / im.file).string(), cv::IMREAD_UNCHANGED);
          if (m.empty()) throw std::runtime_error("cannot be decoded");
          im.width = m.cols;
          im.height = m.rows;
          std::size_t q = 0;
          per[i] = image_candidates(to_float_image(m), static_cast<std::uint32_t>(i), opt, &q);
          im.quads = q;
          quads += q;
        } catch (const std::exception& e) {
          im.status = "unreadable";
          im.reason = e.what();
          per[i].clear();
        }
      }
      {
        const std::lock_guard<std::mutex> lock(mu);
        ++done;
      }
      wake.notify_all();
    }
  };
  // `jobs` workers; the calling thread only reports progress.
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, jobs); ++t) pool.emplace_back(work);
  if (progress) {
    std::unique_lock<std::mutex> lock(mu);
    while (done.load() < n) {
      progress({done.load(), n, quads.load()});
      wake.wait_for(lock, std::chrono::milliseconds(250), [&] { return done.load() == n; });
    }
    lock.unlock();
    progress({n, n, quads.load()});
  }
  for (auto& t : pool) t.join();
  std::size_t total = 0;
  for (const auto& v : per) total += v.size();
  store.records.reserve(total);
  for (auto& v : per) {
    store.records.insert(store.records.end(), v.begin(), v.end());
    std::vector<CandidateRecord>().swap(v);
  }
  store.quads = quads.load();
  store.images = std::move(images);
  return store;
}

}  // namespace tagbench::corpus
