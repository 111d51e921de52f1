// What a condition does to a rendered frame in image space: noise, blur, a lighting gradient, lens
// distortion (occlusion and bent are rendered).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "raytrace/sixdof.hpp"
#include "raytrace/sweep_detail.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

// For every pixel of the distorted image, where it comes from in the pinhole render (Newton on
// r (1 + k1 r^2) = r_d, from r_d: monotone for k1 < 0). Points the model folds over (no preimage) are
// sent far out along their ray, so the border is replicated there.
const std::pair<cv::Mat, cv::Mat>& distortion_maps(double k1) {
  static std::mutex mu;
  static std::map<double, std::pair<cv::Mat, cv::Mat>> maps;
  std::lock_guard lock(mu);
  if (auto it = maps.find(k1); it != maps.end()) return it->second;
  const CameraIntrinsics K = render_camera();
  cv::Mat mx(kRenderHeight, kRenderWidth, CV_32FC1), my(kRenderHeight, kRenderWidth, CV_32FC1);
  for (int v = 0; v < kRenderHeight; ++v) {
    for (int u = 0; u < kRenderWidth; ++u) {
      const double xd = (u - K.cx) / K.fx, yd = (v - K.cy) / K.fy, rd = std::hypot(xd, yd);
      double scale = 1;
      if (rd > 0 && k1 != 0) {
        double r = rd;
        bool ok = false;
        for (int it = 0; it < 60; ++it) {
          const double g = r * (1 + k1 * r * r) - rd, dg = 1 + 3 * k1 * r * r;
          if (!(dg > 1e-9)) break;
          const double step = g / dg;
          r -= step;
          if (std::abs(step) < 1e-14) {
            ok = std::abs(r * (1 + k1 * r * r) - rd) < 1e-9 && 1 + 3 * k1 * r * r > 0;
            break;
          }
        }
        scale = ok ? r / rd : 1e3;
      }
      mx.at<float>(v, u) = static_cast<float>(K.fx * xd * scale + K.cx);
      my.at<float>(v, u) = static_cast<float>(K.fy * yd * scale + K.cy);
    }
  }
  return maps.emplace(k1, std::make_pair(mx, my)).first->second;
}

}  // namespace

cv::Mat apply_effect(const cv::Mat& gray8, const SweepFrame& f) {
  if (gray8.type() != CV_8UC1) throw std::invalid_argument("apply_effect needs an 8-bit gray image");
  const ImageEffect& e = f.effect;
  if (e.camera) return apply_camera_effects(gray8, *e.camera);
  if (e.strength == 0) return gray8;
  cv::Mat out;
  switch (e.condition) {
    case Condition::kNoise: {
      out.create(gray8.size(), CV_8UC1);
      Rng rng{e.seed};
      for (int y = 0; y < gray8.rows; ++y)
        for (int x = 0; x < gray8.cols; ++x)
          out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(
              std::lround(gray8.at<std::uint8_t>(y, x) + e.strength * rng.normal()));
      return out;
    }
    case Condition::kBlur:
      cv::GaussianBlur(gray8, out, cv::Size(), e.strength, e.strength, cv::BORDER_REPLICATE);
      return out;
    case Condition::kGradient: {
      const Eigen::Vector2d u(std::cos(e.direction_deg * kDeg), std::sin(e.direction_deg * kDeg));
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& p : f.truth.corners) {
        lo = std::min(lo, p.dot(u));
        hi = std::max(hi, p.dot(u));
      }
      out.create(gray8.size(), CV_8UC1);
      for (int y = 0; y < gray8.rows; ++y)
        for (int x = 0; x < gray8.cols; ++x) {
          const double w = std::clamp((Eigen::Vector2d(x, y).dot(u) - lo) / (hi - lo), 0.0, 1.0);
          out.at<std::uint8_t>(y, x) =
              cv::saturate_cast<std::uint8_t>(std::lround(gray8.at<std::uint8_t>(y, x) * (1 - e.strength * w)));
        }
      return out;
    }
    case Condition::kDistortion: {
      const auto& [mx, my] = distortion_maps(-e.strength);
      cv::remap(gray8, out, mx, my, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
      return out;
    }
    default: return gray8;  // occlusion and bent are in the render
  }
}

}  // namespace tagbench::bench
