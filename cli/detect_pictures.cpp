#include "cli/detect_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/homography.hpp"

namespace tagbench::cli {
namespace {

cv::Mat to_bgr8(const cv::Mat& img) {
  cv::Mat m8;
  switch (img.depth()) {
    case CV_8U: m8 = img; break;
    case CV_16U: img.convertTo(m8, CV_8U, 1.0 / 257.0); break;
    default: img.convertTo(m8, CV_8U, 255.0); break;  // float images are taken to be in [0, 1]
  }
  cv::Mat bgr;
  if (m8.channels() == 1) cv::cvtColor(m8, bgr, cv::COLOR_GRAY2BGR);
  else if (m8.channels() == 4) cv::cvtColor(m8, bgr, cv::COLOR_BGRA2BGR);
  else bgr = m8.clone();
  return bgr;
}

cv::Mat gray_bgr(const ImageF& g, double gain = 1.0) {
  cv::Mat m(g.height, g.width, CV_8UC1);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      m.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(g.at(x, y) * 255.0 * gain);
  cv::Mat bgr;
  cv::cvtColor(m, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

constexpr int kShift = 4;  // sub-pixel drawing: coordinates in 1/16 px
cv::Point fixed(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x() * (1 << kShift))), static_cast<int>(std::lround(p.y() * (1 << kShift)))};
}
bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::abs(p.x()) < 1e7 && std::abs(p.y()) < 1e7; }

// Outline colours (BGR), none of them the axes' pure red, green or blue.
const cv::Scalar kPalette[] = {{255, 255, 0}, {255, 0, 255}, {0, 255, 255}, {0, 160, 255},
                               {255, 128, 0}, {200, 100, 255}, {128, 255, 128}, {255, 0, 128}};
cv::Scalar palette(std::size_t i) { return kPalette[i % (sizeof kPalette / sizeof kPalette[0])]; }

// A colour from a fixed seed (cluster i always gets the same colour).
cv::Scalar seeded_colour(std::size_t i) {
  cv::RNG rng(0x9e3779b97f4a7c15ULL ^ (static_cast<std::uint64_t>(i) * 0xbf58476d1ce4e5b9ULL + 1));
  return {static_cast<double>(rng.uniform(48, 256)), static_cast<double>(rng.uniform(48, 256)),
          static_cast<double>(rng.uniform(48, 256))};
}

// Whether a payload reading was taken on a detected tag's quad: it has d*d payload samples and each
// lies on one of the tag's payload cell centres (the reading's quad may list its corners in another
// order, so the points are compared as a set).
bool reading_of(const PayloadReading& r, const Detection& d, int width) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(width);
  if (width <= 0 || r.payload_points.size() != n) return false;
  std::vector<Eigen::Vector2d> cells;
  const double cell = 2.0 / (width + 2);
  for (int gy = 2; gy <= width + 1; ++gy)
    for (int gx = 2; gx <= width + 1; ++gx)
      cells.push_back(apply_homography(d.homography, Eigen::Vector2d(-1 + (gx - 0.5) * cell, -1 + (gy - 0.5) * cell)));
  for (const auto& p : r.payload_points) {
    double best = 1e300;
    for (const auto& c : cells) best = std::min(best, (p - c).squaredNorm());
    if (!(best < 0.25)) return false;  // within half a pixel
  }
  return true;
}

}  // namespace

// The paper's Fig. 1: outline, a dot on the printed top-left corner, id, pose axes (x red, y green,
// z blue; z points into the tag, as the tag frame's z does).
cv::Mat draw_detections(const cv::Mat& image, const std::vector<Detection>& dets, const DetectorOptions& opt,
                        bool several_families) {
  cv::Mat out = to_bgr8(image);
  const int thick = std::max(1, static_cast<int>(std::lround(std::min(out.cols, out.rows) / 400.0)));
  for (std::size_t k = 0; k < dets.size(); ++k) {
    const Detection& d = dets[k];
    bool ok = true;
    for (const auto& c : d.corners) ok = ok && finite(c);
    if (!ok) continue;
    const cv::Scalar col = palette(k);
    double edge = 0;
    for (int i = 0; i < 4; ++i) {
      const auto& a = d.corners[static_cast<std::size_t>(i)];
      const auto& b = d.corners[static_cast<std::size_t>((i + 1) % 4)];
      edge += (b - a).norm() / 4;
      cv::line(out, fixed(a), fixed(b), col, thick, cv::LINE_AA, kShift);
    }
    const int r = std::max(2, static_cast<int>(std::lround(edge / 14)));
    cv::circle(out, fixed(d.corners[0]), r << kShift, col, cv::FILLED, cv::LINE_AA, kShift);  // printed top-left

    const std::string text = several_families ? d.family + ":" + std::to_string(d.id) : std::to_string(d.id);
    const double scale = std::clamp(edge / 160.0, 0.3, 4.0);
    const int tt = std::max(1, static_cast<int>(std::lround(scale * 1.5)));
    int base = 0;
    const cv::Size sz = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, tt, &base);
    const cv::Point org(static_cast<int>(std::lround(d.center.x() - sz.width / 2.0)),
                        static_cast<int>(std::lround(d.center.y() + sz.height / 2.0)));
    if (finite(d.center)) {
      cv::putText(out, text, org, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), tt + 2, cv::LINE_AA);
      cv::putText(out, text, org, cv::FONT_HERSHEY_SIMPLEX, scale, col, tt, cv::LINE_AA);
    }

    if (d.pose) {  // drawn over the id text, so the axes' origin stays visible
      const Pose& p = d.pose->pose;
      cv::Mat R(3, 3, CV_64F), rvec, tvec = (cv::Mat_<double>(3, 1) << p.t.x(), p.t.y(), p.t.z());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) R.at<double>(i, j) = p.R(i, j);
      cv::Rodrigues(R, rvec);
      const cv::Matx33d K(opt.camera->fx, 0, opt.camera->cx, 0, opt.camera->fy, opt.camera->cy, 0, 0, 1);
      std::vector<double> dist(5, 0.0);
      if (opt.distortion) dist.assign(opt.distortion->begin(), opt.distortion->end());
      const double h = opt.tag_size / 2;
      const std::vector<cv::Point3d> axes = {{0, 0, 0}, {h, 0, 0}, {0, h, 0}, {0, 0, h}};
      bool in_front = true;
      for (const auto& q : axes) in_front = in_front && (p.R * Eigen::Vector3d(q.x, q.y, q.z) + p.t).z() > 1e-9;
      if (in_front) {
        std::vector<cv::Point2d> img;
        cv::projectPoints(axes, rvec, tvec, K, dist, img);
        const cv::Scalar axis_col[3] = {{0, 0, 255}, {0, 255, 0}, {255, 0, 0}};  // x red, y green, z blue
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector2d a(img[0].x, img[0].y), b(img[static_cast<std::size_t>(i + 1)].x,
                                                          img[static_cast<std::size_t>(i + 1)].y);
          if (finite(a) && finite(b)) cv::line(out, fixed(a), fixed(b), axis_col[i], thick + 1, cv::LINE_AA, kShift);
        }
      }
    }
  }
  return out;
}



std::vector<cv::Mat> stage_pictures(const ImageF& gray, const DetectorTrace& tr, const std::vector<Detection>& dets,
                                    const Detector& det) {
  const DetectorOptions& opt = det.options();
  std::vector<cv::Mat> pics;
  const ImageF& mag = tr.gradient_magnitude;
  const ImageF& dir = tr.gradient_direction;
  // A quad finder without gradients (the default profile's threshold finder) has no gradient,
  // cluster or segment stage: those pictures are empty and not written.
  if (mag.empty()) pics.assign(4, cv::Mat());
  if (!mag.empty()) {
  // Gradient magnitude (the square root of the stored squared magnitude), scaled to its maximum.
  {
    float mx = 0;
    for (const float v : mag.data) mx = std::max(mx, v);
    const double s = mx > 0 ? 255.0 / std::sqrt(static_cast<double>(mx)) : 0.0;
    cv::Mat m(mag.height, mag.width, CV_8UC1);
    for (int y = 0; y < mag.height; ++y)
      for (int x = 0; x < mag.width; ++x)
        m.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(std::sqrt(static_cast<double>(mag.at(x, y))) * s);
    pics.push_back(m);
  }
  // Gradient direction as hue where the magnitude passes min_mag, black elsewhere.
  {
    cv::Mat hsv(dir.height, dir.width, CV_8UC3, cv::Scalar(0, 0, 0));
    for (int y = 0; y < dir.height; ++y)
      for (int x = 0; x < dir.width; ++x) {
        if (!(mag.at(x, y) > opt.segmentation.min_mag)) continue;
        const double hue = (dir.at(x, y) + std::numbers::pi) / (2 * std::numbers::pi) * 180.0;
        hsv.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<std::uint8_t>(std::clamp(hue, 0.0, 179.0)), 255, 255);
      }
    cv::Mat bgr;
    cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
    pics.push_back(bgr);
  }
  // Clusters, each in its own seeded colour.
  {
    cv::Mat m(mag.height, mag.width, CV_8UC3, cv::Scalar(0, 0, 0));
    for (std::size_t i = 0; i < tr.clusters.size(); ++i) {
      const cv::Scalar c = seeded_colour(i);
      const cv::Vec3b v(static_cast<std::uint8_t>(c[0]), static_cast<std::uint8_t>(c[1]), static_cast<std::uint8_t>(c[2]));
      for (const ClusterPixel& p : tr.clusters[i])
        if (p.x >= 0 && p.y >= 0 && p.x < m.cols && p.y < m.rows) m.at<cv::Vec3b>(p.y, p.x) = v;
    }
    pics.push_back(m);
  }
  // Segments over the dimmed image, a notch at each midpoint toward the light side (the right of p0->p1).
  {
    cv::Mat m = gray_bgr(gray, 0.5);
    for (std::size_t i = 0; i < tr.segments.size(); ++i) {
      const Segment& s = tr.segments[i];
      if (!finite(s.p0) || !finite(s.p1) || !(s.length > 0)) continue;
      const cv::Scalar c = seeded_colour(i);
      const Eigen::Vector2d d = (s.p1 - s.p0) / s.length;
      const Eigen::Vector2d right(-d.y(), d.x());
      const Eigen::Vector2d mid = (s.p0 + s.p1) / 2;
      const double notch = std::clamp(s.length * 0.2, 2.0, 8.0);
      cv::line(m, fixed(s.p0), fixed(s.p1), c, 1, cv::LINE_AA, kShift);
      cv::line(m, fixed(mid), fixed(Eigen::Vector2d(mid + notch * right)), c, 1, cv::LINE_AA, kShift);
    }
    pics.push_back(m);
  }
  }  // gradient stages
  // The threshold quad finder's stages, at the segmentation's resolution (none for the gradient finder).
  if (tr.threshold_classes.data.empty()) {
    pics.push_back(cv::Mat());
    pics.push_back(cv::Mat());
  } else {
    // Every pixel's class: dark black, light white, unknown (too little contrast around it) grey.
    const TernaryImage& t = tr.threshold_classes;
    pics.push_back(cv::Mat(t.height, t.width, CV_8UC1, const_cast<std::uint8_t*>(t.data.data())).clone());
    // Each boundary group's dark side in its own seeded colour over the dimmed image; groups too
    // small for the quad fit (under min_points) dark grey.
    const ImageF& base = tr.segmentation_input.empty() ? gray : tr.segmentation_input;
    cv::Mat m = gray_bgr(base, 0.35);
    const BoundaryGroups& g = tr.boundary_groups;
    const std::size_t min_points = static_cast<std::size_t>(std::max(0, opt.threshold_quads.fit.min_points));
    for (std::size_t k = 0; k < g.count(); ++k) {
      const auto pts = g.group(k);
      const cv::Scalar c = pts.size() >= min_points ? seeded_colour(k) : cv::Scalar(90, 90, 90);
      const cv::Vec3b v(static_cast<std::uint8_t>(c[0]), static_cast<std::uint8_t>(c[1]), static_cast<std::uint8_t>(c[2]));
      for (const BoundaryPoint& p : pts) {
        const int x = (p.x2 - p.gx) / 2, y = (p.y2 - p.gy) / 2;  // the point's dark pixel
        if (x >= 0 && y >= 0 && x < m.cols && y < m.rows) m.at<cv::Vec3b>(y, x) = v;
      }
    }
    pics.push_back(m);
  }
  // Every candidate quad; a dot on its first corner.
  {
    cv::Mat m = gray_bgr(gray, 0.5);
    for (std::size_t k = 0; k < tr.quads.size(); ++k) {
      const Quad& q = tr.quads[k];
      bool ok = true;
      for (const auto& c : q.corners) ok = ok && finite(c);
      if (!ok) continue;
      const cv::Scalar c = palette(k);
      for (int i = 0; i < 4; ++i)
        cv::line(m, fixed(q.corners[static_cast<std::size_t>(i)]), fixed(q.corners[static_cast<std::size_t>((i + 1) % 4)]),
                 c, 1, cv::LINE_AA, kShift);
      cv::circle(m, fixed(q.corners[0]), 2 << kShift, c, cv::FILLED, cv::LINE_AA, kShift);
    }
    pics.push_back(m);
  }
  // The sample points (Fig. 4) of the detected tags' quads. (The trace holds a reading for every
  // quad that could be sampled, most of them inside tags; drawing them all hides the tags' own.)
  {
    cv::Mat m = gray_bgr(gray);
    // Each dot has a ring of the opposite shade: white samples sit on white, black ones on black.
    const auto dots = [&](const std::vector<Eigen::Vector2d>& pts, const cv::Scalar& fill, const cv::Scalar& ring) {
      for (const auto& p : pts) {
        if (!finite(p)) continue;
        cv::circle(m, fixed(p), 5 << (kShift - 1), ring, cv::FILLED, cv::LINE_AA, kShift);
        cv::circle(m, fixed(p), 3 << (kShift - 1), fill, cv::FILLED, cv::LINE_AA, kShift);
      }
    };
    for (const PayloadReading& r : tr.readings) {
      bool detected = false;
      for (const Detection& d : dets)
        for (const TagFamily& f : det.families())
          detected = detected || (f.name() == d.family && reading_of(r, d, f.payload_width()));
      if (!detected) continue;
      dots(r.white_points, cv::Scalar(255, 255, 255), cv::Scalar(0, 0, 0));
      dots(r.black_points, cv::Scalar(0, 0, 0), cv::Scalar(255, 255, 255));
      dots(r.payload_points, cv::Scalar(0, 255, 255), cv::Scalar(0, 0, 0));
    }
    pics.push_back(m);
  }
  return pics;
}

std::string encode(const cv::Mat& img, const std::string& ext) {
  std::vector<std::uint8_t> buf;
  if (!cv::imencode(ext, img, buf)) throw std::runtime_error("cannot encode a " + ext + " picture");
  return std::string(reinterpret_cast<const char*>(buf.data()), buf.size());
}

}  // namespace tagbench::cli
