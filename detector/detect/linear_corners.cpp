#include "detect/linear_corners.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "detect/detector.hpp"
#include "detect/photometric_refine.hpp"

namespace tagbench {

namespace {

// v^gamma, by table for the 256 values an 8-bit image gives (v = k / 255) and computed otherwise
// (float powers, as the table; image.hpp's linearised() is the same in double).
struct Linearise {
  explicit Linearise(double gamma) : gamma(static_cast<float>(gamma)) {
    for (int k = 0; k < 256; ++k) table[static_cast<std::size_t>(k)] = std::pow(k / 255.0f, this->gamma);
  }
  float operator()(float v) const {
    const float s = v * 255.0f;
    if (s >= 0 && s <= 255) {
      const int k = static_cast<int>(s + 0.5f);
      if (static_cast<float>(k) / 255.0f == v) return table[static_cast<std::size_t>(k)];
    }
    return std::pow(std::max(0.0f, v), gamma);
  }
  float gamma;
  std::array<float, 256> table{};
};

}  // namespace

void refine_corners_linear(std::span<Detection> detections, const ImageF& img, std::span<const TagFamily> families,
                           double gamma, const EdgeRefineOptions& refine, const LinearCornerOptions& opt) {
  if (gamma == 1.0 || !(gamma > 0 && std::isfinite(gamma)) || img.empty()) return;
  const Linearise linear(gamma);
  EdgeRefineOptions o = refine;
  o.gamma = 1.0;  // the neighbourhood is linearised already
  o.max_corner_shift_px = opt.max_corner_shift_px;
  EdgeRefineScratch scratch;
  ImageF roi;
  // The scan's reach beyond a side (its range, the derivative's half width, the sides' moves) and a pixel for
  // the interpolation: the linearised neighbourhood holds every sample.
  const double reach = o.max_range_px + o.derivative_half_px + 2 * opt.max_corner_shift_px + 2;
  for (Detection& d : detections) {
    const auto f = std::find_if(families.begin(), families.end(), [&](const TagFamily& x) { return x.name() == d.family; });
    if (f == families.end()) continue;
    o.cells_across = f->payload_width() + 2;
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    for (const auto& p : d.corners) {
      if (!p.allFinite()) continue;
      x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y()), x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
    }
    if (!(x1 >= x0 && y1 >= y0)) continue;
    // The tag's neighbourhood with every pixel linearised before it is interpolated: a pixel is the
    // sensor's linear light integrated over its area, encoded; interpolating encoded values and then
    // linearising would bend even a sharp step.
    const int ix0 = std::max(0, static_cast<int>(std::floor(x0 - reach)));
    const int iy0 = std::max(0, static_cast<int>(std::floor(y0 - reach)));
    const int ix1 = std::min(img.width - 1, static_cast<int>(std::ceil(x1 + reach)));
    const int iy1 = std::min(img.height - 1, static_cast<int>(std::ceil(y1 + reach)));
    if (ix1 < ix0 || iy1 < iy0) continue;
    roi.width = ix1 - ix0 + 1, roi.height = iy1 - iy0 + 1;
    roi.data.resize(static_cast<std::size_t>(roi.width) * static_cast<std::size_t>(roi.height));
    for (int y = iy0; y <= iy1; ++y)
      for (int x = ix0; x <= ix1; ++x) roi.at(x - ix0, y - iy0) = linear(img.at(x, y));
    const Eigen::Vector2d shift(ix0, iy0);
    Corners local = d.corners;
    for (auto& p : local) p -= shift;
    auto moved = refine_quad_edges(roi, local, o, scratch);
    if (!moved) continue;
    for (auto& p : *moved) p += shift;
    move_detection_to(d, moved);
  }
}

}  // namespace tagbench
