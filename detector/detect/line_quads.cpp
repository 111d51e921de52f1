#include "detect/line_quads.hpp"

#include <algorithm>
#include <cmath>

#include "detect/blur.hpp"
#include "detect/payload_decode.hpp"

namespace tagbench {

namespace {

// img (at least 2 x 2) at `scale` < 1 into scratch.small: blurred so that, with the resampling's own,
// the blur is LSD's 0.6 px at the new scale, then sampled bilinearly (pixel centres at integers).
void resample(const ImageF& img, double scale, LineQuadScratch& scratch) {
  gaussian_blur(img, 0.6 * std::sqrt(1 / (scale * scale) - 1), scratch.tmp, scratch.blurred);
  const ImageF& src = scratch.blurred;
  ImageF& out = scratch.small;
  out.width = std::max(1, static_cast<int>(img.width * scale));
  out.height = std::max(1, static_cast<int>(img.height * scale));
  out.data.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height));
  for (int y = 0; y < out.height; ++y) {
    const double sy = std::clamp((y + 0.5) / scale - 0.5, 0.0, img.height - 1.0);
    for (int x = 0; x < out.width; ++x)
      out.at(x, y) = sample_bilinear_inside(src, {std::clamp((x + 0.5) / scale - 0.5, 0.0, img.width - 1.0), sy});
  }
}

}  // namespace

bool centre_covered(const Quad& q, std::span<const Corners> covered) {
  const Eigen::Vector2d centre = (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]) / 4;
  return std::any_of(covered.begin(), covered.end(), [&](const Corners& c) { return inside_quad(c, centre); });
}

std::vector<Quad> line_quads(const ImageF& img, std::span<const Corners> covered, const LineQuadOptions& opt,
                             LineQuadScratch& scratch) {
  std::vector<Segment>& segs = scratch.both_ways;
  if (opt.scale < 1 && img.width >= 2 && img.height >= 2) {
    double (*to_full)(double, double) = [](double v, double) { return full_from_half(v); };
    if (opt.scale == 0.5) {  // the 2 x 2 average: cheaper than resampling, and as good on the realistic set
      half_resolution(img, scratch.small);
    } else {
      resample(img, opt.scale, scratch);
      to_full = [](double v, double scale) { return (v + 0.5) / scale - 0.5; };
    }
    segs = detect_line_segments(scratch.small, opt.segments, scratch.segments);
    for (Segment& g : segs) {
      g.p0 = {to_full(g.p0.x(), opt.scale), to_full(g.p0.y(), opt.scale)};
      g.p1 = {to_full(g.p1.x(), opt.scale), to_full(g.p1.y(), opt.scale)};
      g.length /= opt.scale;
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
