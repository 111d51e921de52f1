#pragma once
// Boundaries between a dark and a light component (beyond the paper; AprilTag 2, section III-B):
// wherever a dark pixel and a light pixel are neighbours (right, below, or diagonal below), the point
// half way between them is a boundary point of the pair (dark component, light component). Points
// are grouped by that pair, so a tag's black square and the white ring around it give one group
// even where other dark objects touch the white ring, and two tags side by side never merge.
//
// Coordinates: a point is stored doubled, (x2, y2) = (x0 + x1, y0 + y1) of the two pixels, so it
// sits at (x2 / 2, y2 / 2) in image pixels (pixel centres at integer coordinates, image.hpp).
// (gx, gy) is the unit step from the dark pixel toward the light one (each -1, 0 or 1).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "components.hpp"

namespace tagbench {

struct BoundaryOptions {
  // Components smaller than this (pixels) are ignored: too small to be a tag's square or its white
  // ring, and most of the noise specks in textures (AprilTag 3 uses 25).
  std::uint32_t min_component_pixels = 25;
};

struct BoundaryPoint {
  std::int32_t x2 = 0, y2 = 0;  // doubled coordinates (see above)
  std::int8_t gx = 0, gy = 0;   // toward the light side
};

// The bounding box of non-empty `points`, in their doubled coordinates.
struct DoubledBox {
  int xmin = 0, xmax = 0, ymin = 0, ymax = 0;
};
inline DoubledBox bounding_box(std::span<const BoundaryPoint> points) {
  DoubledBox b{points[0].x2, points[0].x2, points[0].y2, points[0].y2};
  for (const auto& p : points) {
    b.xmin = std::min(b.xmin, p.x2), b.xmax = std::max(b.xmax, p.x2);
    b.ymin = std::min(b.ymin, p.y2), b.ymax = std::max(b.ymax, p.y2);
  }
  return b;
}

// Groups of points; group g is points[offsets[g] .. offsets[g + 1]), in the order each group's
// first point was met in a raster scan (deterministic).
struct BoundaryGroups {
  std::vector<BoundaryPoint> points;
  std::vector<std::uint32_t> offsets;  // count() + 1 entries (empty when there are no groups)
  std::size_t count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::span<const BoundaryPoint> group(std::size_t g) const {
    return {points.data() + offsets[g], points.data() + offsets[g + 1]};
  }
};

struct BoundaryScratch {
  std::vector<std::uint64_t> keys;    // open-addressing table of component pairs
  std::vector<std::uint32_t> values;  // group index per table slot
  std::vector<BoundaryPoint> raw;     // points in scan order
  std::vector<std::uint32_t> raw_group;
  std::vector<std::uint32_t> fill;
  std::vector<std::uint32_t> big_label;  // per run: its component's id if at least min_component_pixels, else none
};

// Collects and groups the boundary points of `img` (labelled by `comp`) into `out` (storage reused).
void group_boundaries(const TernaryImage& img, const Components& comp, const BoundaryOptions& opt,
                      BoundaryScratch& scratch, BoundaryGroups& out);

BoundaryGroups group_boundaries(const TernaryImage& img, const Components& comp, const BoundaryOptions& opt = {});

// The buffers of one pass from an image to boundary groups (adaptive_threshold, threshold.hpp;
// connected_components; group_boundaries), kept between frames: the threshold quad finder's whole
// image and each crop of its low-contrast look use one each.
struct BoundaryPassScratch {
  ThresholdScratch threshold;
  TernaryImage ternary;
  Components components;
  ComponentScratch component_scratch;
  BoundaryScratch boundary_scratch;
  BoundaryGroups groups;
};

}  // namespace tagbench
