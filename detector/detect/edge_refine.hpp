#pragma once
// Edge refinement of a quad (beyond the paper; AprilTag 2/3 "refine_edges"): each side is re-fitted
// from the image itself. At evenly spaced points along the side (the corners' neighbourhoods
// skipped), the intensity step across the side is searched within +-search_range px along its
// normal; the step position is the mean of the offsets weighted by the squared central difference
// where it rises outward (dark inside to light outside), and a line is fitted through those
// positions. Corners become the intersections of the refitted lines. This recovers accuracy that a
// coarse candidate stage lost (a threshold boundary is quantised to half pixels, and to whole
// pixels of the half-size image when decimating).
//
// Quad convention: clockwise on screen (quad_search.hpp), dark square inside. Pixel centres at
// integer coordinates. A side with fewer than 2 usable samples keeps its line through the corners.
#include "detect/homography.hpp"
#include "detect/image.hpp"

namespace tagbench {

struct EdgeRefineOptions {
  double search_range = 1.0;  // px either side of the current side (use 1 + decimation factor - 1 when halving: 2)
  double step = 0.25;         // px between samples along the normal
  int min_samples = 16;       // samples per side at least; long sides get one per 8 px
};

// The refined corners; the input corners when a pair of refitted lines is (nearly) parallel.
Corners refine_quad_edges(const ImageF& img, const Corners& quad, const EdgeRefineOptions& opt = {});

}  // namespace tagbench
