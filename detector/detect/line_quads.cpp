#include "detect/line_quads.hpp"

#include <algorithm>
#include <cmath>
#include <algorithm>

#include "detect/blur.hpp"

namespace tagbench {

bool centre_covered(const Quad& q, std::span<const Corners> covered) {
  const Eigen::Vector2d centre = (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]) / 4;
  return std::any_of(covered.begin(), covered.end(), [&](const Corners& c) { return inside_quad(c, centre); });
}

std::vector<Quad> line_quads(const ImageF& img, std::span<const Corners> covered, const LineQuadOptions& opt,
                             LineQuadScratch& scratch) {
  std::vector<Segment>& segs = scratch.both_ways;
  if (opt.scale == 0.5) {  // the 2 x 2 average: cheaper, and on the realistic set no worse than below
    half_resolution(img, scratch.half);
    segs = detect_line_segments(scratch.half, opt.segments, scratch.segments);
    for (Segment& g : segs) {
      g.p0 = {full_from_half(g.p0.x()), full_from_half(g.p0.y())};
      g.p1 = {full_from_half(g.p1.x()), full_from_half(g.p1.y())};
      g.length *= 2;
    }
  } else if (opt.scale < 1) {
    // Anti-aliased (the blur that, with the resampling's own, makes sigma 0.6 at the new scale, as
    // LSD's scaling does), then sampled bilinearly; the edges' ends mapped back.
    const double s = opt.scale;
    gaussian_blur(img, 0.6 * std::sqrt(1 / (s * s) - 1), scratch.tmp, scratch.blurred);
    ImageF& small = scratch.half;
    const int w = std::max(1, static_cast<int>(img.width * s)), h = std::max(1, static_cast<int>(img.height * s));
    small.width = w, small.height = h;
    small.data.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    const ImageF& src = scratch.blurred;
    for (int y = 0; y < h; ++y) {
      const double sy = std::clamp((y + 0.5) / s - 0.5, 0.0, img.height - 1.0);
      const int y0 = std::min(static_cast<int>(sy), img.height - 2 < 0 ? 0 : img.height - 2);
      const float fy = static_cast<float>(sy - y0);
      for (int x = 0; x < w; ++x) {
        const double sx = std::clamp((x + 0.5) / s - 0.5, 0.0, img.width - 1.0);
        const int x0 = std::min(static_cast<int>(sx), img.width - 2 < 0 ? 0 : img.width - 2);
        const float fx = static_cast<float>(sx - x0);
        const float* r0 = src.data.data() + src.index(x0, y0);
        const float* r1 = img.height > 1 ? r0 + src.width : r0;
        const float top = r0[0] + fx * (r0[img.width > 1 ? 1 : 0] - r0[0]);
        const float bottom = r1[0] + fx * (r1[img.width > 1 ? 1 : 0] - r1[0]);
        small.data[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] = top + fy * (bottom - top);
      }
    }
    segs = detect_line_segments(small, opt.segments, scratch.segments);
    for (Segment& g : segs) {
      g.p0 = ((g.p0.array() + 0.5) / s - 0.5).matrix();
      g.p1 = ((g.p1.array() + 0.5) / s - 0.5).matrix();
      g.length /= s;
    }
  } else {
    segs = detect_line_segments(img, opt.segments, scratch.segments);
  }
  const std::size_t n = segs.size();
  for (std::size_t i = 0; i < n; ++i) {  // every edge also the other way round
    Segment s = segs[i];
    std::swap(s.p0, s.p1);
    s.theta = std::atan2(s.p1.y() - s.p0.y(), s.p1.x() - s.p0.x());
    segs.push_back(s);
  }
  QuadSearchOptions qs;
  qs.close_enough = CloseEnoughRule::kCode2012;  // 6 + length / 2: pieces of a side leave gaps at corners
  qs.min_tag_size = opt.min_side_px;
  std::vector<Quad> quads = find_quads(segs, qs);
  std::erase_if(quads, [&](const Quad& q) {
    for (int i = 0; i < 4; ++i)
      if ((q.corners[i] - q.corners[(i + 1) % 4]).norm() > opt.max_side_px) return true;
    return centre_covered(q, covered);
  });
  for (auto& q : quads) q.observed_perimeter = 0;
  return quads;
}

}  // namespace tagbench
