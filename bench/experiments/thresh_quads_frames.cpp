// thresh_quads' frame sources (thresh_quads_detail.hpp): realistic, small and defocused frames with
// their tags' true corners, and the images of a folder for the speed and natural-image modes.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "experiments/thresh_quads_detail.hpp"
#include "realistic/realistic_set.hpp"
#include "scenes.hpp"

namespace tagbench::bench::experiments::thresh_quads_detail {

double quad_area(const Corners& c) {
  double a = 0;
  for (std::size_t i = 0; i < 4; ++i) a += c[i].x() * c[(i + 1) % 4].y() - c[(i + 1) % 4].x() * c[i].y();
  return std::abs(a) / 2;
}

std::vector<Frame> realistic_frames(int n, const std::string& family, std::uint64_t seed, double blur) {
  bench::RealisticSettings s;
  if (blur >= 0) s.blur_sigma_px = {blur, blur};  // a fixed defocus instead of the calibrated range
  s.family = family;
  s.seed = seed;
  std::vector<Frame> frames;
  for (int i = 0; i < n; ++i) {
    auto rf = bench::make_realistic_frame(s, i);
    Frame f{rf.image, {}};
    for (const auto& t : rf.tags) f.tags.push_back({t.id, t.corners, t.black_square_px, t.tilt_deg});
    frames.push_back(std::move(f));
  }
  return frames;
}

// make_scene at 5x (tags 8-25 % of the height), INTER_AREA down to 240 x 180 (tags ~14-45 px),
// Gaussian noise sigma 3 (of 255), JPEG quality 75.
std::vector<Frame> small_frames(int n, const std::string& family, std::uint32_t seed) {
  std::vector<Frame> frames;
  std::mt19937 rng(seed);
  for (int i = 0; i < n; ++i) {
    const int k = 5, w = 240, h = 180;
    Scene sc = make_scene(w * k, h * k, family, 3, seed + static_cast<std::uint32_t>(i));
    cv::Mat small;
    cv::resize(sc.image, small, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    cv::Mat noise(small.size(), CV_32F);
    cv::randn(noise, 0, 3);
    cv::Mat f32;
    small.convertTo(f32, CV_32F);
    f32 += noise;
    f32.convertTo(small, CV_8U);
    std::vector<uchar> jpg;
    cv::imencode(".jpg", small, jpg, {cv::IMWRITE_JPEG_QUALITY, 75});
    Frame f{cv::imdecode(jpg, cv::IMREAD_GRAYSCALE), {}};
    for (const auto& t : sc.tags) {
      Corners c;
      // A full-resolution pixel centre x maps to (x + 0.5) / k - 0.5 after area averaging.
      for (std::size_t j = 0; j < 4; ++j) c[j] = (t.corners[j] + Eigen::Vector2d(0.5, 0.5)) / k - Eigen::Vector2d(0.5, 0.5);
      f.tags.push_back({t.id, c, std::sqrt(quad_area(c))});
    }
    frames.push_back(std::move(f));
  }
  (void)rng;
  return frames;
}

// make_scene at 640 x 480 (tags 38-120 px), Gaussian blur sigma px (defocus), noise sigma 2, JPEG q90.
std::vector<Frame> defocus_frames(int n, const std::string& family, double sigma) {
  std::vector<Frame> frames;
  for (int i = 0; i < n; ++i) {
    Scene sc = make_scene(640, 480, family, 4, 500 + static_cast<std::uint32_t>(i));
    cv::Mat b, f32;
    cv::GaussianBlur(sc.image, b, cv::Size(), sigma);
    cv::Mat noise(b.size(), CV_32F);
    cv::setRNGSeed(500 + i);
    cv::randn(noise, 0, 2);
    b.convertTo(f32, CV_32F);
    f32 += noise;
    f32.convertTo(b, CV_8U);
    std::vector<uchar> jpg;
    cv::imencode(".jpg", b, jpg, {cv::IMWRITE_JPEG_QUALITY, 90});
    Frame f{cv::imdecode(jpg, cv::IMREAD_GRAYSCALE), {}};
    for (const auto& t : sc.tags) f.tags.push_back({t.id, t.corners, std::sqrt(quad_area(t.corners))});
    frames.push_back(std::move(f));
  }
  return frames;
}

std::vector<std::string> image_files(const std::string& dir, std::size_t max) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    auto ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".webp") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.size() > max) {  // an even spread over the sorted list (every group represented)
    std::vector<std::string> pick;
    for (std::size_t i = 0; i < max; ++i) pick.push_back(files[i * files.size() / max]);
    files = pick;
  }
  return files;
}

std::vector<cv::Mat> load_gray(const std::vector<std::string>& files) {
  std::vector<cv::Mat> v;
  for (const auto& f : files) {
    cv::Mat m = cv::imread(f, cv::IMREAD_GRAYSCALE);
    if (m.empty()) continue;
    if (std::max(m.cols, m.rows) > 2048) {  // as the corpus scan does
      const double s = 2048.0 / std::max(m.cols, m.rows);
      cv::resize(m, m, cv::Size(), s, s, cv::INTER_AREA);
    }
    v.push_back(m);
  }
  return v;
}

}  // namespace tagbench::bench::experiments::thresh_quads_detail
