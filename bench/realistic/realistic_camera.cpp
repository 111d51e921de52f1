// The realistic set's camera (realistic_parts.hpp): what a small camera does between the light on the
// sensor and the JPEG a user hands a detector.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "realistic/realistic_parts.hpp"

namespace tagbench::bench::realistic_parts {

namespace {

// A line PSF of `length` pixels at `angle_deg`, area-normalised, drawn 8x supersampled so that
// sub-pixel lengths blur sub-pixel amounts.
cv::Mat line_kernel(double length, double angle_deg) {
  const int half = static_cast<int>(std::ceil(length / 2)) + 1, n = 2 * half + 1, ss = 8;
  cv::Mat big(n * ss, n * ss, CV_32F, cv::Scalar(0));
  const double a = angle_deg * M_PI / 180, dx = std::cos(a) * length / 2, dy = std::sin(a) * length / 2;
  const double c = (n * ss - 1) / 2.0;
  cv::line(big, cv::Point2d(c - dx * ss, c - dy * ss), cv::Point2d(c + dx * ss, c + dy * ss), cv::Scalar(1.0), ss);
  cv::Mat k;
  cv::resize(big, k, cv::Size(n, n), 0, 0, cv::INTER_AREA);
  return k / cv::sum(k)[0];
}

}  // namespace

cv::Mat disk_kernel(double radius) {
  const int r = static_cast<int>(std::ceil(radius + 0.5)), n = 2 * r + 1, ss = 8;
  cv::Mat k(n, n, CV_32F, cv::Scalar(0));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      int inside = 0;  // of the pixel's ss x ss samples
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          const double px = x - r - 0.5 + (sx + 0.5) / ss, py = y - r - 0.5 + (sy + 0.5) / ss;
          inside += px * px + py * py <= radius * radius;
        }
      k.at<float>(y, x) = static_cast<float>(inside);
    }
  return k / cv::sum(k)[0];
}

cv::Mat apply_camera(const cv::Mat& linear, const RealisticSettings& st, Draws& dr, CameraDegradation& d,
                     std::vector<std::uint8_t>& jpeg) {
  cv::Mat v = linear.clone();
  jpeg.clear();
  if (!st.degrade) {
    cv::Mat out;
    v.convertTo(out, CV_8U, 255.0);  // rounds and saturates
    return out;
  }
  // Optics: defocus, then the camera's (or the hand's) motion during the exposure.
  d.blur_sigma_px = dr.uniform(st.blur_sigma_px);
  if (d.blur_sigma_px > 0 && st.disk_defocus)
    cv::filter2D(v, v, -1, disk_kernel(2 * d.blur_sigma_px), cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  else if (d.blur_sigma_px > 0)
    cv::GaussianBlur(v, v, cv::Size(0, 0), d.blur_sigma_px, d.blur_sigma_px, cv::BORDER_REFLECT);
  d.motion_blur_px = dr.uniform(st.motion_blur_px);
  d.motion_angle_deg = dr.uniform(0, 180);
  if (d.motion_blur_px > 0.05)
    cv::filter2D(v, v, -1, line_kernel(d.motion_blur_px, d.motion_angle_deg), cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  else
    d.motion_blur_px = 0;
  // Sensor: photon shot noise (Poisson, as a normal of variance = electrons) and read noise.
  d.full_well_e = dr.uniform(st.full_well_e);
  d.read_noise_e = dr.uniform(st.read_noise_e);
  cv::Mat z(v.size(), CV_32F);
  cv::RNG rng(dr.next());
  rng.fill(z, cv::RNG::NORMAL, 0.0, 1.0);
  const double fw = d.full_well_e, rn2 = d.read_noise_e * d.read_noise_e;
  d.gamma = st.gamma;
  const double inv_gamma = 1 / st.gamma;
  cv::Mat encoded(v.size(), CV_32F);
  for (int y = 0; y < v.rows; ++y) {
    const float* pv = v.ptr<float>(y);
    const float* pz = z.ptr<float>(y);
    float* pe = encoded.ptr<float>(y);
    for (int x = 0; x < v.cols; ++x) {
      const double e = std::max(0.0, static_cast<double>(pv[x])) * fw;
      const double s = std::clamp((e + std::sqrt(e + rn2) * pz[x]) / fw, 0.0, 1.0);
      pe[x] = static_cast<float>(255 * std::pow(s, inv_gamma));
    }
  }
  // Processing: sharpening (it also sharpens the noise, and rings at edges, as real cameras do).
  d.sharpen_amount = dr.uniform(st.sharpen_amount);
  if (d.sharpen_amount > 0) {
    cv::Mat soft;
    cv::GaussianBlur(encoded, soft, cv::Size(0, 0), st.sharpen_sigma_px, st.sharpen_sigma_px, cv::BORDER_REFLECT);
    encoded += d.sharpen_amount * (encoded - soft);
  }
  cv::Mat out;
  encoded.convertTo(out, CV_8U);  // rounds and saturates
  // JPEG, as the photograph is stored; the detectors get the decoded file.
  d.jpeg_quality = static_cast<int>(std::lround(dr.uniform(st.jpeg_quality)));
  if (!cv::imencode(".jpg", out, jpeg, {cv::IMWRITE_JPEG_QUALITY, d.jpeg_quality}))
    throw std::runtime_error("realistic frame: JPEG encoding failed");
  cv::Mat decoded = cv::imdecode(jpeg, cv::IMREAD_GRAYSCALE);
  if (decoded.empty()) throw std::runtime_error("realistic frame: JPEG decoding failed");
  return decoded;
}

}  // namespace tagbench::bench::realistic_parts
