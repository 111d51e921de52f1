#include "detect/detector.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "detect/blur.hpp"
#include "detect/gradient.hpp"
#include "detect/homography.hpp"

namespace tagbench {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point& t) {
  const auto now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - t).count();
  t = now;
  return ms;
}

double perimeter(const Corners& c) {
  double p = 0;
  for (int i = 0; i < 4; ++i) p += (c[static_cast<std::size_t>((i + 1) % 4)] - c[static_cast<std::size_t>(i)]).norm();
  return p;
}

Corners undistort(const Corners& c, const CameraIntrinsics& K, const std::array<double, 5>& dist) {
  std::vector<cv::Point2d> in, out;
  for (const auto& p : c) in.emplace_back(p.x(), p.y());
  const cv::Matx33d Km(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  const cv::Matx<double, 1, 5> D(dist[0], dist[1], dist[2], dist[3], dist[4]);
  cv::undistortPoints(in, out, Km, D, cv::noArray(), Km);  // P = K keeps pixel units
  Corners r;
  for (std::size_t i = 0; i < 4; ++i) r[i] = Eigen::Vector2d(out[i].x, out[i].y);
  return r;
}

}  // namespace

struct DetectorWorkspace::Impl {
  ImageF gray;             // the float image (cv::Mat input only; ImageF input is read in place)
  cv::Mat colour;          // scaled colour image before the gray conversion
  ImageF blur_tmp;         // horizontal pass of the blurs
  ImageF seg_in, dec_in;   // segmentation input; optional separately blurred decoding image
  Gradients gradients;
  SegmentationScratch seg;
  Clusters clusters;
};

DetectorWorkspace::DetectorWorkspace() : impl_(std::make_unique<Impl>()) {}
DetectorWorkspace::~DetectorWorkspace() = default;
DetectorWorkspace::DetectorWorkspace(DetectorWorkspace&&) noexcept = default;
DetectorWorkspace& DetectorWorkspace::operator=(DetectorWorkspace&&) noexcept = default;

std::vector<DetectorWorkspace::Buffer> DetectorWorkspace::buffers() const {
  if (!impl_) return {};  // moved from
  const Impl& w = *impl_;
  auto of = [](const char* name, const auto& v) {
    return Buffer{name, v.data(), v.capacity() * sizeof(v[0])};
  };
  return {of("gray", w.gray.data),
          Buffer{"colour", w.colour.data, w.colour.empty() ? 0 : w.colour.total() * w.colour.elemSize()},
          of("blur_tmp", w.blur_tmp.data),
          of("seg_in", w.seg_in.data),
          of("dec_in", w.dec_in.data),
          of("gradient_mag", w.gradients.mag),
          of("gradient_theta", w.gradients.theta),
          of("edges", w.seg.edges),
          of("edges_sorted", w.seg.sorted),
          of("weight_start", w.seg.weight_start),
          of("union_find_parent", w.seg.parent),
          of("union_find_stats", w.seg.stats),
          of("cluster_of", w.seg.cluster_of),
          of("cluster_count", w.seg.count),
          of("cluster_fill", w.seg.fill),
          of("cluster_pixels", w.clusters.pixels),
          of("cluster_offsets", w.clusters.offsets)};
}

std::size_t DetectorWorkspace::capacity_bytes() const {
  std::size_t sum = 0;
  for (const Buffer& b : buffers()) sum += b.capacity_bytes;
  return sum;
}

void DetectorWorkspace::release() {
  if (impl_) *impl_ = Impl();  // fresh members: the old storage is freed
}

Detector::Detector(DetectorOptions options) : opt_(std::move(options)) {
  if (opt_.families.empty()) throw std::invalid_argument("no tag family given");
  for (const auto& f : opt_.families) families_.push_back(load_family(f));
  if (opt_.max_hamming < 0 || opt_.max_hamming > 16)
    throw std::invalid_argument("max hamming " + std::to_string(opt_.max_hamming) + " is outside 0..16");
  if (!(opt_.min_decision_margin >= 0 && opt_.min_decision_margin <= 1))
    throw std::invalid_argument("minimum decision margin " + std::to_string(opt_.min_decision_margin) +
                                " is outside 0..1");
  if (!(opt_.seg_sigma >= 0) || !(opt_.decode_sigma >= 0) || !std::isfinite(opt_.seg_sigma) ||
      !std::isfinite(opt_.decode_sigma))
    throw std::invalid_argument("blur sigma must be finite and >= 0");
  if (opt_.camera && !opt_.camera->valid())
    throw std::invalid_argument("camera intrinsics must be finite with fx, fy > 0");
  if (opt_.camera && !(opt_.tag_size > 0 && std::isfinite(opt_.tag_size)))
    throw std::invalid_argument("tag size must be > 0 (metres) when intrinsics are given");
  if (opt_.distortion) {
    if (!opt_.camera) throw std::invalid_argument("distortion needs camera intrinsics");
    for (const double k : *opt_.distortion)
      if (!std::isfinite(k)) throw std::invalid_argument("distortion coefficients must be finite");
  }
  if (opt_.max_pixels < 1 || opt_.max_pixels > kMaxPixelsCeiling)
    throw std::invalid_argument("max pixels " + std::to_string(opt_.max_pixels) + " is outside 1.." +
                                std::to_string(kMaxPixelsCeiling));
}

void Detector::check_size(long long width, long long height) const {
  if (width * height <= opt_.max_pixels) return;
  throw std::invalid_argument("image " + std::to_string(width) + "x" + std::to_string(height) + " (" +
                              std::to_string(width * height) + " pixels) is over the detector's limit of " +
                              std::to_string(opt_.max_pixels) + " pixels (DetectorOptions::max_pixels)");
}

std::vector<Detection> Detector::detect(const cv::Mat& image, DetectorTrace* trace, StageTimings* timings) const {
  DetectorWorkspace ws;
  return detect(image, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const ImageF& gray, DetectorTrace* trace, StageTimings* timings) const {
  DetectorWorkspace ws;
  return detect(gray, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const cv::Mat& image, DetectorWorkspace& ws, DetectorTrace* trace,
                                        StageTimings* timings) const {
  if (image.empty() || image.cols < 1 || image.rows < 1) throw std::invalid_argument("empty image");
  check_size(image.cols, image.rows);  // before the conversion allocates anything
  if (!ws.impl_) ws = DetectorWorkspace();  // a moved-from workspace is usable again
  to_float_image(image, ws.impl_->gray, ws.impl_->colour);
  return run(ws.impl_->gray, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const ImageF& gray, DetectorWorkspace& ws, DetectorTrace* trace,
                                        StageTimings* timings) const {
  if (gray.empty()) throw std::invalid_argument("empty image");
  check_size(gray.width, gray.height);
  // Every stage indexes data[y * width + x]: a short vector would be read past its end.
  if (gray.data.size() != static_cast<std::size_t>(gray.width) * static_cast<std::size_t>(gray.height))
    throw std::invalid_argument("image data has " + std::to_string(gray.data.size()) + " values, not " +
                                std::to_string(gray.width) + "x" + std::to_string(gray.height));
  if (!ws.impl_) ws = DetectorWorkspace();
  return run(gray, ws, trace, timings);
}

std::vector<Detection> Detector::run(const ImageF& gray, DetectorWorkspace& workspace, DetectorTrace* trace,
                                     StageTimings* timings) const {
  DetectorWorkspace::Impl& ws = *workspace.impl_;
  StageTimings tm;
  const auto t_start = Clock::now();
  auto t = t_start;

  // 1. Blur (and halve) for segmentation; the decoding image is separate.
  const bool halve = opt_.half_resolution && gray.width >= 4 && gray.height >= 4;
  if (halve)
    blur_and_halve(gray, opt_.seg_sigma, ws.blur_tmp, ws.seg_in);
  else
    gaussian_blur(gray, opt_.seg_sigma, ws.blur_tmp, ws.seg_in);
  const ImageF& seg_in = ws.seg_in;
  if (opt_.decode_sigma > 0) gaussian_blur(gray, opt_.decode_sigma, ws.blur_tmp, ws.dec_in);
  const ImageF& decode_image = opt_.decode_sigma > 0 ? ws.dec_in : gray;
  tm.blur = ms_since(t);

  // 2. Gradients; 3. clusters; 4. segments.
  compute_gradients(seg_in, opt_.segmentation.min_mag, ws.gradients);
  const Gradients& g = ws.gradients;
  tm.gradient = ms_since(t);
  segment_clusters(g, opt_.segmentation, ws.seg, ws.clusters);
  const Clusters& clusters = ws.clusters;
  tm.segmentation = ms_since(t);
  std::vector<Segment> segments = fit_segments(clusters, opt_.line_fit);
  if (halve)
    for (auto& s : segments) s = segment_full_from_half(s);
  tm.line_fit = ms_since(t);

  // 5. Quads.
  std::vector<Quad> quads = find_quads(segments, opt_.quad_search);
  tm.quads = ms_since(t);
  tm.segment_count = segments.size();
  tm.quad_count = quads.size();

  // 6. Payloads, decoded against every family (one reading per payload width).
  std::vector<Detection> found;
  int max_d = 0;
  for (const TagFamily& f : families_) max_d = std::max(max_d, f.payload_width());
  PayloadOptions payload = opt_.payload;
  payload.quick_reject = false;  // done below from the corners, before the homography
  for (const Quad& q : quads) {
    if (opt_.payload.quick_reject && !border_contrast_plausible(decode_image, q.corners, max_d, opt_.payload.min_contrast))
      continue;
    const auto H = tag_homography(q.corners);
    if (!H) continue;
    std::array<std::optional<PayloadReading>, 9> by_width;  // one reading per payload width d
    std::array<bool, 9> read{};
    Detection best;
    bool have = false;
    for (const TagFamily& f : families_) {
      const auto d = static_cast<std::size_t>(f.payload_width());
      if (!read[d]) {
        by_width[d] = read_payload(decode_image, *H, static_cast<int>(d), payload, trace != nullptr);
        read[d] = true;
      }
      const auto& reading = by_width[d];
      if (!reading) continue;
      const auto dec = f.decode(reading->bits, opt_.max_hamming);
      if (!dec || (have && dec->hamming >= best.hamming)) continue;
      have = true;
      best.family = f.name();
      best.id = dec->id;
      best.hamming = dec->hamming;
      best.rotation = dec->rotation;
      best.decision_margin = reading->margin;
    }
    if (trace)
      for (auto& r : by_width)
        if (r) trace->readings.push_back(std::move(*r));
    if (!have) continue;
    // The printed top-left corner is quad corner `rotation` (observed = rotate90^r(code)).
    for (int i = 0; i < 4; ++i)
      best.corners[static_cast<std::size_t>(i)] = q.corners[static_cast<std::size_t>((i + best.rotation) % 4)];
    best.homography = *tag_homography(best.corners);
    best.center = apply_homography(best.homography, Eigen::Vector2d::Zero());
    best.observed_perimeter = q.observed_perimeter;
    found.push_back(std::move(best));
  }

  // Duplicates: same family and id, centres closer than 1/16 of the two quads' summed perimeters;
  // keep the lower hamming, then the longer observed perimeter (NOTES).
  std::vector<Detection> out;
  for (auto& d : found) {
    bool replaced = false, dropped = false;
    for (auto& o : out) {
      if (o.family != d.family || o.id != d.id) continue;
      if ((o.center - d.center).norm() >= (perimeter(o.corners) + perimeter(d.corners)) / 16) continue;
      const bool better = d.hamming < o.hamming || (d.hamming == o.hamming && d.observed_perimeter > o.observed_perimeter);
      if (better && !replaced) {
        o = d;
        replaced = true;
      } else {
        dropped = true;
      }
      break;
    }
    if (!replaced && !dropped) out.push_back(std::move(d));
  }
  std::erase_if(out, [&](const Detection& d) { return d.decision_margin < opt_.min_decision_margin; });
  tm.decode = ms_since(t);

  // 7. Poses.
  if (opt_.camera) {
    for (auto& d : out) {
      const Corners c = opt_.distortion ? undistort(d.corners, *opt_.camera, *opt_.distortion) : d.corners;
      if (opt_.refine_pose) {
        const auto sols = tag_pose_solutions(c, *opt_.camera, opt_.tag_size);
        if (!sols.empty()) d.pose = sols[0];
        if (sols.size() > 1) d.pose_alternative = sols[1];
      } else if (const auto H = tag_homography(c)) {
        const Pose p = pose_from_homography(*H, *opt_.camera, opt_.tag_size);
        d.pose = PoseSolution{p, corner_rms_error(p, c, *opt_.camera, opt_.tag_size)};
      }
    }
  }
  tm.pose = ms_since(t);
  tm.total = std::chrono::duration<double, std::milli>(Clock::now() - t_start).count();
  for (auto& d : out) d.timings = tm;
  if (timings) *timings = tm;

  if (trace) {
    trace->segmentation_input = seg_in;
    trace->gradient_magnitude = ImageF(g.width, g.height);
    trace->gradient_direction = ImageF(g.width, g.height);
    trace->gradient_magnitude.data.assign(g.mag.begin(), g.mag.end());
    trace->gradient_direction.data.assign(g.theta.begin(), g.theta.end());
    trace->clusters = clusters;  // a copy: the workspace keeps its buffers
    trace->segments = std::move(segments);
    trace->quads = std::move(quads);
  }
  return out;
}

}  // namespace tagbench
