#include "detect/quad_search.hpp"

#include <algorithm>
#include <cmath>

namespace tagbench {
namespace {

// Signed turning angle from direction a to direction b, in (-pi, pi].
double turn(double a, double b) {
  double t = b - a;
  while (t > M_PI) t -= 2 * M_PI;
  while (t <= -M_PI) t += 2 * M_PI;
  return t;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Segment starts bucketed on a coarse grid, for "which segments start near this point?".
class StartGrid {
 public:
  StartGrid(const std::vector<Segment>& segs, double cell) : cell_(cell) {
    if (segs.empty()) return;
    min_ = max_ = segs[0].p0;
    for (const auto& s : segs) {
      min_ = min_.cwiseMin(s.p0);
      max_ = max_.cwiseMax(s.p0);
    }
    w_ = static_cast<int>((max_.x() - min_.x()) / cell_) + 1;
    h_ = static_cast<int>((max_.y() - min_.y()) / cell_) + 1;
    offsets_.assign(static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_) + 1, 0);
    for (const auto& s : segs) ++offsets_[bucket(s.p0) + 1];
    for (std::size_t i = 1; i < offsets_.size(); ++i) offsets_[i] += offsets_[i - 1];
    items_.resize(segs.size());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t i = 0; i < segs.size(); ++i) items_[fill[bucket(segs[i].p0)]++] = static_cast<int>(i);
  }

  // Calls f(index) for every segment whose start may lie within r of p (a superset: the caller checks).
  template <class F>
  void near(const Eigen::Vector2d& p, double r, F&& f) const {
    if (items_.empty()) return;
    const int x0 = std::max(0, static_cast<int>(std::floor((p.x() - r - min_.x()) / cell_)));
    const int x1 = std::min(w_ - 1, static_cast<int>(std::floor((p.x() + r - min_.x()) / cell_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((p.y() - r - min_.y()) / cell_)));
    const int y1 = std::min(h_ - 1, static_cast<int>(std::floor((p.y() + r - min_.y()) / cell_)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t b = static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x);
        for (std::uint32_t k = offsets_[b]; k < offsets_[b + 1]; ++k) f(items_[k]);
      }
  }

 private:
  std::size_t bucket(const Eigen::Vector2d& p) const {
    const int x = std::clamp(static_cast<int>((p.x() - min_.x()) / cell_), 0, w_ - 1);
    const int y = std::clamp(static_cast<int>((p.y() - min_.y()) / cell_), 0, h_ - 1);
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x);
  }
  double cell_;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero(), max_ = Eigen::Vector2d::Zero();
  int w_ = 0, h_ = 0;
  std::vector<std::uint32_t> offsets_;
  std::vector<int> items_;
};

// Geometry checks of a candidate quad (corners in search order, counter-clockwise on screen).
bool acceptable(const Corners& c, const QuadSearchOptions& opt) {
  double shortest = 1e300, longest = 0;
  for (int i = 0; i < 4; ++i) {
    const double l = (c[static_cast<std::size_t>((i + 1) % 4)] - c[static_cast<std::size_t>(i)]).norm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  const double d1 = (c[2] - c[0]).norm(), d2 = (c[3] - c[1]).norm();
  if (!(shortest >= opt.min_tag_size) || d1 < opt.min_tag_size || d2 < opt.min_tag_size) return false;
  if (longest > opt.max_aspect * shortest) return false;
  // Convex, and consistently turning the way the segments do.
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d a = c[static_cast<std::size_t>((i + 1) % 4)] - c[static_cast<std::size_t>(i)];
    const Eigen::Vector2d b = c[static_cast<std::size_t>((i + 2) % 4)] - c[static_cast<std::size_t>((i + 1) % 4)];
    if (!(cross(a, b) < 0)) return false;
  }
  return true;
}

}  // namespace

double close_enough_radius(CloseEnoughRule rule, double length) {
  switch (rule) {
    case CloseEnoughRule::kPaper2011: return 2 * length + 5;
    case CloseEnoughRule::kCode2010: return 0.5 * length;
    case CloseEnoughRule::kCode2012: return 6 + 0.5 * length;
  }
  return 0;
}

std::optional<Eigen::Vector2d> line_intersection(const Segment& a, const Segment& b) {
  const Eigen::Vector2d da = a.p1 - a.p0, db = b.p1 - b.p0;
  const double den = cross(da, db);
  if (std::abs(den) < 1e-9 * da.norm() * db.norm()) return std::nullopt;
  const double s = cross(b.p0 - a.p0, db) / den;
  return a.p0 + s * da;
}

std::vector<Quad> find_quads(const std::vector<Segment>& segs, const QuadSearchOptions& opt) {
  std::vector<Quad> quads;
  const StartGrid grid(segs, opt.grid_cell);
  std::array<int, 4> path{};
  // The segments that may follow each segment (start close enough to its end, turn the right way, lines
  // not parallel) depend only on that segment, not on the path: find them once with the lookup grid, in
  // grid order, with the corner where the two lines meet.
  struct Child {
    int index;
    Eigen::Vector2d corner;  // intersection of the parent's and the child's lines
  };
  std::vector<std::vector<Child>> children(segs.size());
  for (std::size_t parent = 0; parent < segs.size(); ++parent) {
    const Segment& p = segs[parent];
    const double r = close_enough_radius(opt.close_enough, p.length);
    grid.near(p.p1, r, [&](int child) {
      const Segment& c = segs[static_cast<std::size_t>(child)];
      if ((c.p0 - p.p1).squaredNorm() > r * r) return;
      if (!(cross(p.p1 - p.p0, c.p1 - c.p0) < 0)) return;  // winding: each turn goes the same way
      const auto x = line_intersection(p, c);
      if (x) children[parent].push_back({child, *x});
    });
  }
  // Whether segment k lies on its side from corner a to corner b: the side runs the segment's way and
  // the segment's midpoint projects between a and b.
  const auto on_side = [&](int k, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Segment& sg = segs[static_cast<std::size_t>(k)];
    const Eigen::Vector2d d = sg.p1 - sg.p0;
    if (!((b - a).dot(d) > 0)) return false;
    const double t = (0.5 * (sg.p0 + sg.p1) - a).dot(b - a) / (b - a).squaredNorm();
    return t >= 0 && t <= 1;
  };
  // Half of that test when only one corner is known yet: the midpoint lies before the side's end
  // corner (ends = true) or after its start corner (ends = false), along the segment's direction.
  const auto before_or_after = [&](int k, const Eigen::Vector2d& corner, bool ends) {
    const Segment& sg = segs[static_cast<std::size_t>(k)];
    const double s = (corner - 0.5 * (sg.p0 + sg.p1)).dot(sg.p1 - sg.p0);
    return ends ? s >= 0 : s <= 0;
  };
  for (int s0 = 0; s0 < static_cast<int>(segs.size()) && quads.size() < opt.max_quads; ++s0) {
    path[0] = s0;
    for (const Child& c1 : children[static_cast<std::size_t>(s0)]) {
      // Each quad is found from each of its four segments: keep the search rooted at the smallest index.
      const int s1 = c1.index;
      if (s1 <= s0) continue;
      // Corner c1 ends side s0 and starts side s1.
      if (opt.segments_on_sides && (!before_or_after(s0, c1.corner, true) || !before_or_after(s1, c1.corner, false)))
        continue;
      path[1] = s1;
      for (const Child& c2 : children[static_cast<std::size_t>(s1)]) {
        const int s2 = c2.index;
        if (s2 <= s0 || s2 == s1) continue;
        // Side s1's corners are fixed once s2 is chosen: prune here what the final check would refuse.
        if (opt.segments_on_sides && (!on_side(s1, c1.corner, c2.corner) || !before_or_after(s2, c2.corner, false)))
          continue;
        path[2] = s2;
        for (const Child& c3 : children[static_cast<std::size_t>(s2)]) {
          const int s3 = c3.index;
          if (s3 <= s0 || s3 == s1 || s3 == s2 || quads.size() >= opt.max_quads) continue;
          if (opt.segments_on_sides && !on_side(s2, c2.corner, c3.corner)) continue;
          // Closing: the first segment must follow the last as a child would (close enough, right turn).
          const Segment& last = segs[static_cast<std::size_t>(s3)];
          const Segment& first = segs[static_cast<std::size_t>(s0)];
          const double r = close_enough_radius(opt.close_enough, last.length);
          if ((first.p0 - last.p1).squaredNorm() > r * r) continue;
          if (!(cross(last.p1 - last.p0, first.p1 - first.p0) < 0)) continue;
          path[3] = s3;
          double winding = 0;
          for (int i = 0; i < 4; ++i)
            winding += turn(segs[static_cast<std::size_t>(path[static_cast<std::size_t>(i)])].theta,
                            segs[static_cast<std::size_t>(path[static_cast<std::size_t>((i + 1) % 4)])].theta);
          if (winding < opt.winding_min || winding > opt.winding_max) continue;
          const auto closing = line_intersection(last, first);
          if (!closing) continue;
          // ccw[i]: the corner between side i and side i + 1.
          const Corners ccw = {c1.corner, c2.corner, c3.corner, *closing};
          if (!acceptable(ccw, opt)) continue;
          if (opt.segments_on_sides && (!on_side(s0, ccw[3], ccw[0]) || !on_side(s3, ccw[2], ccw[3]))) continue;
          Quad q;
          // Clockwise on screen for the tag corner convention: reverse the counter-clockwise order.
          q.corners = {ccw[3], ccw[2], ccw[1], ccw[0]};
          q.segments = path;
          for (const int k : path) q.observed_perimeter += segs[static_cast<std::size_t>(k)].length;
          quads.push_back(q);
        }
      }
    }
  }
  return quads;
}

}  // namespace tagbench
