// The sixdof sweep's camera: OpenCV's lens model (distort, undistort, projected corners), the rule for
// a tag in view, and the image effects (lens, defocus, noise, quantization).
#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "raytrace/sixdof.hpp"
#include "raytrace/sweep_detail.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

cv::Matx33d camera_matrix(const CameraIntrinsics& K) { return {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1}; }

cv::Vec<double, 5> coefficients(const std::array<double, 5>& d) { return {d[0], d[1], d[2], d[3], d[4]}; }

std::vector<cv::Point2d> project(const Pose& pose, const std::vector<cv::Point3d>& points, const std::array<double, 5>& d,
                                 const CameraIntrinsics& K) {
  cv::Mat R(3, 3, CV_64F), rvec;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) R.at<double>(i, k) = pose.R(i, k);
  cv::Rodrigues(R, rvec);
  const cv::Vec3d tvec(pose.t.x(), pose.t.y(), pose.t.z());
  std::vector<cv::Point2d> out;
  cv::projectPoints(points, rvec, tvec, camera_matrix(K), coefficients(d), out);
  return out;
}

// For every pixel of the distorted image, where it is in the pinhole render (undistort_pixel); pixels
// without a preimage are sent far out so that the border is replicated there.
const std::pair<cv::Mat, cv::Mat>& lens_maps(const std::array<double, 5>& d, int width, int height) {
  static std::mutex mu;
  static std::map<std::tuple<std::array<double, 5>, int, int>, std::pair<cv::Mat, cv::Mat>> maps;
  std::lock_guard lock(mu);
  const auto key = std::make_tuple(d, width, height);
  if (auto it = maps.find(key); it != maps.end()) return it->second;
  const CameraIntrinsics K = render_camera();
  std::vector<cv::Point2d> grid;
  grid.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) grid.emplace_back(u, v);
  std::vector<cv::Point2d> pinhole;
  const cv::TermCriteria until(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12);
  cv::undistortPoints(grid, pinhole, camera_matrix(K), coefficients(d), cv::noArray(), camera_matrix(K), until);
  // Check every preimage by distorting it back (one projectPoints call on the normalized rays).
  std::vector<cv::Point3d> rays;
  rays.reserve(pinhole.size());
  for (const auto& p : pinhole) rays.emplace_back((p.x - K.cx) / K.fx, (p.y - K.cy) / K.fy, 1.0);
  const std::vector<cv::Point2d> back = project(Pose{}, rays, d, K);
  cv::Mat mx(height, width, CV_32FC1), my(height, width, CV_32FC1);
  for (int v = 0, i = 0; v < height; ++v)
    for (int u = 0; u < width; ++u, ++i) {
      const auto& p = pinhole[static_cast<std::size_t>(i)];
      const auto& b = back[static_cast<std::size_t>(i)];
      const bool ok = std::isfinite(p.x) && std::isfinite(p.y) && std::hypot(b.x - u, b.y - v) < 1e-6;
      mx.at<float>(v, u) = ok ? static_cast<float>(p.x) : -1e6f;
      my.at<float>(v, u) = ok ? static_cast<float>(p.y) : -1e6f;
    }
  return maps.emplace(key, std::make_pair(mx, my)).first->second;
}

}  // namespace

Eigen::Vector2d distort_pixel(const Eigen::Vector2d& p, const std::array<double, 5>& d, const CameraIntrinsics& K) {
  const auto out = project(Pose{}, {cv::Point3d((p.x() - K.cx) / K.fx, (p.y() - K.cy) / K.fy, 1.0)}, d, K);
  return {out[0].x, out[0].y};
}

std::optional<Eigen::Vector2d> undistort_pixel(const Eigen::Vector2d& q, const std::array<double, 5>& d,
                                               const CameraIntrinsics& K) {
  std::vector<cv::Point2d> in{{q.x(), q.y()}}, out;
  const cv::TermCriteria until(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12);
  cv::undistortPoints(in, out, camera_matrix(K), coefficients(d), cv::noArray(), camera_matrix(K), until);
  const Eigen::Vector2d p(out[0].x, out[0].y);
  if (!p.allFinite() || (distort_pixel(p, d, K) - q).norm() > 1e-6) return std::nullopt;
  return p;
}

Corners project_corners(const Pose& pose, double tag_size, const std::array<double, 5>& d, const CameraIntrinsics& K) {
  const double h = tag_size / 2;  // tag frame: x to the right edge, y to the bottom edge
  const auto p = project(pose, {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}}, d, K);
  Corners c;
  for (std::size_t k = 0; k < 4; ++k) c[k] = Eigen::Vector2d(p[k].x, p[k].y);
  return c;
}

bool sixdof_fits(const Pose& pose, double printed_size, const std::array<double, 5>& d, double margin_px) {
  const double h = printed_size / 2;
  const double xs[4] = {-h, h, h, -h}, ys[4] = {-h, -h, h, h};
  std::vector<cv::Point3d> outline;
  constexpr int kPerEdge = 16;
  for (int e = 0; e < 4; ++e)
    for (int k = 0; k < kPerEdge; ++k) {
      const double a = static_cast<double>(k) / kPerEdge;
      const int n = (e + 1) % 4;
      outline.emplace_back(xs[e] + a * (xs[n] - xs[e]), ys[e] + a * (ys[n] - ys[e]), 0);
    }
  for (const auto& p : outline)
    if (pose.R.row(2).dot(Eigen::Vector3d(p.x, p.y, p.z)) + pose.t.z() <= 0) return false;  // behind the camera
  const auto inside = [&](const std::vector<cv::Point2d>& pts) {
    return std::all_of(pts.begin(), pts.end(), [&](const cv::Point2d& q) {
      return q.x >= margin_px && q.x <= kRenderWidth - 1 - margin_px && q.y >= margin_px &&
             q.y <= kRenderHeight - 1 - margin_px;
    });
  };
  return inside(project(pose, outline, {}, render_camera())) && inside(project(pose, outline, d, render_camera()));
}

cv::Mat apply_camera_effects(const cv::Mat& gray8, const CameraEffects& e) {
  if (gray8.type() != CV_8UC1) throw std::invalid_argument("apply_camera_effects needs an 8-bit gray image");
  if (e.quantization_bits < 1 || e.quantization_bits > 8)
    throw std::invalid_argument("quantization bits must be in 1..8");
  cv::Mat f;
  gray8.convertTo(f, CV_32F);
  if (std::any_of(e.distortion.begin(), e.distortion.end(), [](double k) { return k != 0; })) {
    const auto& [mx, my] = lens_maps(e.distortion, gray8.cols, gray8.rows);
    cv::Mat warped;
    cv::remap(f, warped, mx, my, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    f = warped;
  }
  if (e.defocus_sigma_px > 0) {
    cv::Mat blurred;
    cv::GaussianBlur(f, blurred, cv::Size(), e.defocus_sigma_px, e.defocus_sigma_px, cv::BORDER_REPLICATE);
    f = blurred;
  }
  cv::Mat out(gray8.size(), CV_8UC1);
  Rng rng{e.noise_seed};
  const double step = 255.0 / ((1 << e.quantization_bits) - 1);  // 8 bits: 1 level
  for (int y = 0; y < f.rows; ++y)
    for (int x = 0; x < f.cols; ++x) {
      double v = f.at<float>(y, x);
      if (e.noise_sigma > 0) v += e.noise_sigma * rng.normal();
      v = std::clamp(std::round(v / step) * step, 0.0, 255.0);
      out.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(std::lround(v));
    }
  return out;
}

}  // namespace tagbench::bench
