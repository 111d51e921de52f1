#pragma once
// Connected components of the thresholded image (beyond the paper; AprilTag 2, section III-B): the
// dark pixels and the light pixels each form regions; unknown pixels (threshold.hpp) belong to none.
// Dark regions are 4-connected and light regions 8-connected (the usual dual pair, so a dark
// region and the light region around it separate cleanly: a diagonal dark-dark step never cuts a
// light region in two and vice versa).
//
// The union-find runs over horizontal runs of equal class, not pixels: a row of a tag's edge is one
// or two runs instead of dozens of pixels, so there are far fewer unions and finds.
#include <cstdint>
#include <vector>

#include "threshold.hpp"

namespace tagbench {

inline constexpr std::uint32_t kNoComponent = 0xFFFFFFFFu;

// A horizontal run [x0, x1] (inclusive) of one class in one row.
struct ClassRun {
  std::int32_t x0 = 0, x1 = 0;
  std::uint8_t value = 0;
};

// The labelling, run-length encoded: every row is a sequence of runs that covers it, each run with
// its component's id. A pixel's label is its run's (label_at); no per-pixel image is written, since
// the boundary stage, its one reader, walks the rows in order (writing and reading a 4-byte label
// per pixel was a third of this stage's time).
struct Components {
  int width = 0, height = 0;
  std::vector<ClassRun> runs;            // row by row, left to right, covering every row
  std::vector<std::uint32_t> row_start;  // runs of row y: [row_start[y], row_start[y + 1]); height + 1 entries
  std::vector<std::uint32_t> run_label;  // per run: its component's id, kNoComponent for unknown runs; a
                                         // component's id is the index of its first run in raster order
  std::vector<std::uint32_t> size;       // per id: the component's pixel count (ids index into it; unused ids hold 0)
  std::uint32_t count = 0;               // number of components (dark and light)

  // The component id of pixel (x, y) inside the image, kNoComponent when it is unknown (a binary
  // search in its row).
  std::uint32_t label_at(int x, int y) const;
};

// Every pixel's label (row-major), for tests and diagnostics.
std::vector<std::uint32_t> label_image(const Components& c);

struct ComponentScratch {
  std::vector<std::uint32_t> parent;  // union-find over runs
};

// Labels `img` into `out` (resized; storage reused from frame to frame). dark_eight swaps the pair:
// dark regions 8-connected and light regions 4-connected (a rotated one-pixel black border is a
// diagonal staircase, which 4-connectivity cuts into pieces).
void connected_components(const TernaryImage& img, ComponentScratch& scratch, Components& out, bool dark_eight = false);

// Convenience form with its own scratch.
Components connected_components(const TernaryImage& img, bool dark_eight = false);

}  // namespace tagbench
