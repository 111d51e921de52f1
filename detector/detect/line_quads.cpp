#include "detect/line_quads.hpp"

#include <algorithm>
#include <cmath>

namespace tagbench {

bool centre_covered(const Quad& q, std::span<const Corners> covered) {
  const Eigen::Vector2d centre = (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]) / 4;
  return std::any_of(covered.begin(), covered.end(), [&](const Corners& c) { return inside_quad(c, centre); });
}

std::vector<Quad> line_quads(const ImageF& img, std::span<const Corners> covered, const LineQuadOptions& opt,
                             LineQuadScratch& scratch) {
  std::vector<Segment>& segs = scratch.both_ways;
  segs = detect_line_segments(img, opt.segments, scratch.segments);
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
