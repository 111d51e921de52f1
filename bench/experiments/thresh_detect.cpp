#include "experiments/thresh_detect.hpp"

#include <chrono>

#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/detector.hpp"
#include "detect/homography.hpp"

namespace tagbench::bench::experiments {
namespace {

double perimeter(const Corners& c) {
  double p = 0;
  for (std::size_t i = 0; i < 4; ++i) p += (c[(i + 1) % 4] - c[i]).norm();
  return p;
}

struct Decoded {
  Found f;
  Eigen::Vector2d center;
  double observed_perimeter = 0;
};

}  // namespace

std::vector<Found> decode_quads(const std::vector<Quad>& quads, const ImageF& gray, const TagFamily& family,
                                int max_hamming, const PayloadOptions& payload_opt) {
  const int d = family.payload_width();
  PayloadOptions payload = payload_opt;
  payload.quick_reject = false;  // done from the corners first, as detector.cpp does
  std::vector<Decoded> found;
  for (const Quad& q : quads) {
    if (payload_opt.quick_reject && !border_contrast_plausible(gray, q.corners, d, payload_opt.min_contrast)) continue;
    const auto H = tag_homography(q.corners);
    if (!H) continue;
    const auto reading = read_payload(gray, *H, d, payload);
    if (!reading) continue;
    const auto dec = family.decode(reading->bits, max_hamming);
    if (!dec) continue;
    Decoded x;
    x.f.family = family.name();
    x.f.id = dec->id;
    x.f.hamming = dec->hamming;
    x.f.decision_margin = reading->margin;
    for (std::size_t i = 0; i < 4; ++i) x.f.corners[i] = q.corners[(i + static_cast<std::size_t>(dec->rotation)) % 4];
    x.center = apply_homography(*tag_homography(x.f.corners), Eigen::Vector2d::Zero());
    x.observed_perimeter = q.observed_perimeter;
    found.push_back(std::move(x));
  }
  std::vector<Decoded> out;
  for (auto& x : found) {
    bool replaced = false, dropped = false;
    for (auto& o : out) {
      if (o.f.id != x.f.id) continue;
      if ((o.center - x.center).norm() >= (perimeter(o.f.corners) + perimeter(x.f.corners)) / 16) continue;
      const bool better =
          x.f.hamming < o.f.hamming || (x.f.hamming == o.f.hamming && x.observed_perimeter > o.observed_perimeter);
      if (better && !replaced) {
        o = x;
        replaced = true;
      } else {
        dropped = true;
      }
      break;
    }
    if (!replaced && !dropped) out.push_back(std::move(x));
  }
  std::vector<Found> r;
  for (auto& x : out) r.push_back(std::move(x.f));
  return r;
}

ThreshDetector::ThreshDetector(std::string name, ThreshDetectorOptions opt)
    : Comparator(std::move(name)), opt_(std::move(opt)), family_(load_family(opt_.family)) {
  if (opt_.with_paper_quads) {
    DetectorOptions o;
    o.families = {opt_.family};
    paper_ = std::make_unique<Detector>(o);
  }
}

ThreshDetector::~ThreshDetector() = default;

std::vector<Found> ThreshDetector::detect(const cv::Mat& gray8) {
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  to_float_image(gray8, gray_, colour_);
  auto t1 = Clock::now();
  find_threshold_quads(gray_, opt_.quads, ws_, quads_, &stats_.quads);
  if (opt_.second_pass) {
    find_threshold_quads(gray_, *opt_.second_pass, ws2_, quads2_);
    quads_.insert(quads_.end(), quads2_.begin(), quads2_.end());
  }
  if (paper_) {
    DetectorTrace trace;
    paper_->detect(gray_, &trace);
    quads_.insert(quads_.end(), trace.quads.begin(), trace.quads.end());
  }
  auto t2 = Clock::now();
  auto out = decode_quads(quads_, gray_, family_, opt_.max_hamming, opt_.payload);
  auto t3 = Clock::now();
  stats_.ms_convert = std::chrono::duration<double, std::milli>(t1 - t0).count();
  stats_.ms_decode = std::chrono::duration<double, std::milli>(t3 - t2).count();
  return out;
}

}  // namespace tagbench::bench::experiments
