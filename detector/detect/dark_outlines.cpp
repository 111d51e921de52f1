#include "detect/dark_outlines.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "detect/line_quads.hpp"  // centre_covered
#include "detect/payload_decode.hpp"  // border_worth_refining

namespace tagbench {

namespace {
DoubledBox merged(const DoubledBox& a, const DoubledBox& b) {
  return {std::min(a.xmin, b.xmin), std::max(a.xmax, b.xmax), std::min(a.ymin, b.ymin), std::max(a.ymax, b.ymax)};
}
double longer_side_px(const DoubledBox& b) { return 0.5 * std::max(b.xmax - b.xmin, b.ymax - b.ymin); }

// Calls fn(a, b) for every a < b of `items` (sorted by their box's xmin) whose boxes, each grown by
// margin (doubled px, both boxes together), overlap: a sweep along x.
template <class Fn>
void for_each_overlapping_pair(const std::vector<DarkOutlineScratch::Member>& items, int margin, Fn&& fn) {
  for (std::size_t a = 0; a < items.size(); ++a)
    for (std::size_t b = a + 1; b < items.size() && items[b].box.xmin <= items[a].box.xmax + margin; ++b)
      if (items[b].box.ymin <= items[a].box.ymax + margin && items[a].box.ymin <= items[b].box.ymax + margin) fn(a, b);
}
}  // namespace

std::vector<Quad> dark_outline_quads(const BoundaryGroups& groups, const Components& components, const ImageF& img,
                                     std::span<const Corners> covered, const QuadFitOptions& fit,
                                     const EdgeRefineOptions& refine, const DarkOutlineOptions& opt,
                                     QuadFitScratch& fit_scratch, DarkOutlineScratch& s,
                                     const ThresholdQuadOptions::RefineCheck& check,
                                     std::span<const std::uint8_t> gave_quad) {
  std::vector<Quad> out;
  if (!opt.enabled) return out;
  if (components.width != img.width || components.height != img.height)
    throw std::invalid_argument("dark_outline_quads: components of a " + std::to_string(components.width) + "x" +
                                std::to_string(components.height) + " image for a " + std::to_string(img.width) +
                                "x" + std::to_string(img.height) + " image");
  s.joined.points.clear();
  s.joined.offsets.assign(1, 0);
  s.from_cluster.clear();
  // Whether n groups whose box is `box` are joined: min_groups..max_groups of them, of tag size.
  const auto joinable = [&](std::size_t n, const DoubledBox& box) {
    const double size = longer_side_px(box);
    return n >= static_cast<std::size_t>(opt.min_groups) && n <= static_cast<std::size_t>(opt.max_groups) &&
           size >= opt.min_size_px && size <= opt.max_size_px;
  };
  const auto add_group = [&](std::uint32_t g) {
    const auto pts = groups.group(g);
    s.joined.points.insert(s.joined.points.end(), pts.begin(), pts.end());
  };
  const auto close_joined = [&](bool from_cluster) {
    s.joined.offsets.push_back(static_cast<std::uint32_t>(s.joined.points.size()));
    s.from_cluster.push_back(from_cluster);
  };
  // The groups by_component[i..j) (one component's, too many or too far apart to join whole), each at
  // most max_size_px across, clustered by overlapping boxes; each cluster of min_groups..max_groups
  // groups whose box is of tag size joined.
  const auto join_overlapping = [&](std::size_t i, std::size_t j) {
    s.cluster.clear();
    for (std::size_t k = i; k < j; ++k) {
      const DoubledBox b = bounding_box(groups.group(s.by_component[k].second));
      if (longer_side_px(b) <= opt.max_size_px)
        s.cluster.push_back({b, s.by_component[k].second, static_cast<std::uint32_t>(s.cluster.size())});
    }
    if (s.cluster.size() < 2) return;
    std::sort(s.cluster.begin(), s.cluster.end(), [](const auto& a, const auto& b) { return a.box.xmin < b.box.xmin; });
    for (std::uint32_t k = 0; k < s.cluster.size(); ++k) s.cluster[k].parent = k;
    const auto root = [&](std::uint32_t k) {
      while (s.cluster[k].parent != k) k = s.cluster[k].parent = s.cluster[s.cluster[k].parent].parent;
      return k;
    };
    for_each_overlapping_pair(s.cluster, 0, [&](std::size_t a, std::size_t b) {
      const std::uint32_t ra = root(static_cast<std::uint32_t>(a)), rb = root(static_cast<std::uint32_t>(b));
      if (ra != rb) s.cluster[std::max(ra, rb)].parent = std::min(ra, rb);
    });
    // Members in order of their root (each cluster's members in sweep order).
    s.members.clear();
    for (std::uint32_t k = 0; k < s.cluster.size(); ++k) s.members.emplace_back(root(k), k);
    std::sort(s.members.begin(), s.members.end());
    for (std::size_t a = 0, b = 0; a < s.members.size(); a = b) {
      DoubledBox box = s.cluster[s.members[a].second].box;
      for (b = a + 1; b < s.members.size() && s.members[b].first == s.members[a].first; ++b)
        box = merged(box, s.cluster[s.members[b].second].box);
      if (!joinable(b - a, box)) continue;
      for (std::size_t k = a; k < b; ++k) add_group(s.cluster[s.members[k].second].group);
      close_joined(true);
    }
  };
  // Joins the groups that share the component on one side of their first point (-1: the dark side,
  // as the step (gx, gy) points from the dark pixel to the light one; 1: the light side).
  const auto join_by = [&](int side) {
    s.by_component.clear();
    for (std::size_t g = 0; g < groups.count(); ++g) {
      const BoundaryPoint& p = groups.group(g).front();
      s.by_component.emplace_back(components.label_at((p.x2 + side * p.gx) / 2, (p.y2 + side * p.gy) / 2),
                                  static_cast<std::uint32_t>(g));
    }
    std::sort(s.by_component.begin(), s.by_component.end());
    for (std::size_t i = 0, j = 0; i < s.by_component.size(); i = j) {
      DoubledBox box = bounding_box(groups.group(s.by_component[i].second));
      for (j = i + 1; j < s.by_component.size() && s.by_component[j].first == s.by_component[i].first; ++j)
        box = merged(box, bounding_box(groups.group(s.by_component[j].second)));
      const std::size_t n = j - i;
      if (s.by_component[i].first == kNoComponent) continue;
      if (!joinable(n, box)) {
        if (opt.overlap_clusters && n >= static_cast<std::size_t>(opt.min_groups)) join_overlapping(i, j);
        continue;
      }
      for (std::size_t k = i; k < j; ++k) add_group(s.by_component[k].second);
      close_joined(false);
    }
  };
  join_by(-1);
  if (opt.by_light) join_by(1);
  if (opt.failed_pairs && gave_quad.size() == groups.count()) {
    s.failed.clear();
    for (std::size_t g = 0; g < groups.count(); ++g) {
      if (gave_quad[g] || groups.group(g).size() < static_cast<std::size_t>(opt.pair_min_points)) continue;
      const DoubledBox b = bounding_box(groups.group(g));
      if (longer_side_px(b) <= opt.max_size_px) s.failed.push_back({b, static_cast<std::uint32_t>(g), 0});
    }
    std::sort(s.failed.begin(), s.failed.end(), [](const auto& a, const auto& b) {
      return a.box.xmin < b.box.xmin || (a.box.xmin == b.box.xmin && a.group < b.group);
    });
    const int m = static_cast<int>(std::lround(4 * opt.pair_margin_px));  // both boxes grown: doubled px
    for_each_overlapping_pair(s.failed, m, [&](std::size_t a, std::size_t b) {
      const DoubledBox &ba = s.failed[a].box, &bb = s.failed[b].box, u = merged(ba, bb);
      if (!joinable(2, u)) return;
      if (std::min(longer_side_px(ba), longer_side_px(bb)) < opt.pair_min_share * longer_side_px(u)) return;
      add_group(s.failed[a].group);
      add_group(s.failed[b].group);
      close_joined(true);
    });
  }
  if (s.joined.offsets.size() == 1) s.joined.offsets.clear();
  s.fitted.clear();
  QuadFitOptions f = fit;
  f.outer.ring_check = f.outer.ring_check && opt.ring_check;
  if (!opt.outline_only) {
    fit_quads(s.joined, img, f, fit_scratch, s.fitted);
  } else {
    QuadFitOptions fc = fit;  // an overlap cluster's fit: its ring is whole, its border the broken part
    fc.outer.ring_check = fc.outer.ring_check && opt.overlap_ring_check;
    for (std::size_t g = 0; g < s.joined.count(); ++g) {
      const QuadFitOptions& fg = s.from_cluster[g] ? fc : f;
      outer_outline_points(s.joined.group(g), fg.outer, fit_scratch.outer, fit_scratch.side,
                           static_cast<std::size_t>(std::max(fg.min_points, 4)));
      auto c = fit_outline(fit_scratch.side, img, fg, fit_scratch);
      if (!c && fg.outer.innermost) c = fit_innermost_outline(img, fg, fit_scratch);
      if (c) s.fitted.push_back(fitted_quad(*c));
    }
  }
  for (const Quad& q : s.fitted) {
    if (centre_covered(q, covered)) continue;
    // Refused by the pre-filter: left as fitted, for the decoder's pre-filter to refuse by the same
    // test (the quad stays in the trace, where --explain finds it), as the threshold quads' refine_check.
    if (opt.check_before_refining && check.enabled &&
        !border_worth_refining(img, q.corners, check.payload_width, check.min_contrast, opt.slack_sides)) {
      out.push_back(q);
      continue;
    }
    if (const auto c = refine_quad_edges(img, q.corners, refine, s.refine)) {
      out.push_back(q);
      out.back().corners = *c;
    }
  }
  return out;
}

}  // namespace tagbench
