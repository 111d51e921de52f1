#pragma once
// Beyond the paper: a small quad read but decoded by no family gets another reading through a model
// of a lens's defocus (issue 17: small tags in photographs).
//
// Why: a defocused lens spreads a point over a disk, whose transfer function has a zero. On a tag of
// 12-24 px (cells of 1.5-3 px) a disk of 0.7-1.2 cells' radius cancels, or inverts, the pattern at
// about the cell pitch: a cell between two of the other colour reads as their colour however it is
// sampled or sharpened (payload_area.hpp's Laplacian sharpening assumes a Gaussian spread, with no
// zero). On the realistic set under a disk blur, tags found under a Gaussian of the same sigma were
// misread by 4-13 bits from their true corners (docs/default-profile.md, session 43).
//
// Model. The black square's cells are sampled at M x M points each (M = samples_per_cell) through
// the quad's homography; every sample is modelled as a + b (W p), where p is the printed pattern
// over the grid of cells (a white cell 1, a black 0; the white ring and one more cell round it
// assumed white, the black border black, the payload unknown), W the fraction of a disk of radius
// rho (in cells; 0 = a point sample) centred on the sample that falls on each cell, and a, b the
// black level and the contrast. Unknowns a, b and b p_i for every payload cell i make the model
// linear; a Tikhonov term (regularization) pulls each p_i toward 1/2 where the disk's zero leaves
// it unobserved. Per rho the solution is one fixed matrix times the samples (built once per
// family width and radius, DefocusModels).
//
// Steps, for each quad read but decoded by no family (QuadOutcome kNotDecoded) whose sides lie in
// [min_side_px, max_side_px] and whose centre lies in no tag found so far, and for each family
// whose minimum Hamming distance is at least min_family_hamming:
//   1. hypothesis: at every radius, the payload solved at one sample per cell and thresholded at
//      b / 2; the nearest rotated code within max_hypothesis_bits of any radius' reading (fewest
//      bits), kept when the model with that code explains the samples (mean squared residual over
//      b^2, per cell, at most max_hypothesis_cost: texture fits no code's blurred pattern);
//   2. placement: the quad's eight corner coordinates and the radius fitted to that code's blurred
//      pattern at samples_per_cell^2 samples per cell (coordinate descent on the residual, steps
//      from initial_step_px halved down to final_step_px; corners kept within max_corner_shift_px);
//   3. test: the payload solved again at the fitted corners and radius must decode within the
//      family's corrected bits less spare_bits to the same code in the same rotation.
// As for the code refit (code_refit.hpp), step 3 is fitted to the hypothesis and so not an
// independent reading; a homography and a radius cannot make a 36-bit reading agree with a code
// it is far from, and only families with a large minimum distance are tried.
//
// Units: pixels, except radii (cells of the tag). The image is the unblurred input (linear or
// gamma-encoded as given: the model is fitted to the values as they are).
#include <span>
#include <vector>

#include <Eigen/Core>

#include "../codes/tag_family.hpp"
#include "image.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct Detection;    // detector.hpp
struct QuadOutcome;  // detector.hpp

struct DefocusReadOptions {
  bool enabled = true;  // DetectorOptions::paper(): off (measured: docs/default-profile.md, session 43)
  // Disk radii tried, in cells of the tag; 0 = a point sample (no blur). Sorted ascending, each >= 0.
  // Five, not eight (0, 0.6 .. 1.2 in steps of 0.1): as many tags on the realistic set's two seeds
  // for 84 % of the reading's instructions; four ({0, 0.7, 0.9, 1.1}) cost half as much but found
  // fewer (docs/default-profile.md, session 44).
  std::vector<double> radii_cells{0, 0.6, 0.8, 1.0, 1.2};
  double regularization = 0.15;     // weight of the pull of each payload cell toward 1/2 (per sample row)
  int max_hypothesis_bits = 7;      // step 1: the nearest code at most this far from a reading
  double max_hypothesis_cost = 1.2; // step 1: mean squared residual / b^2 per cell, at most (1.5 until
                                    // session 46: 3 % more of the detector's instructions on realistic
                                    // frames, the placements of hypotheses that fail, for 1 tag in 1384)
  int spare_bits = 1;               // step 3: within the family's corrected bits less these (0: one
                                    // false detection in 200 realistic frames, 1: none)
  int samples_per_cell = 2;         // step 2 and 3: M x M samples per cell
  double initial_step_px = 0.4;     // step 2: the coordinate descent's first step ...
  double final_step_px = 0.05;      // ... halved down to this
  double max_corner_shift_px = 2.5; // step 2: no corner further than this from the quad's
  double min_side_px = 8;           // quads whose shortest side is under this are left alone (px)
  double max_side_px = 64;          // and those whose longest side is over this (px)
  int min_family_hamming = 10;      // only families at least this far apart (36h11, 36h10)
};

// The fixed matrices of the model for one payload width d, per radius (see above). Built once per
// detector (Detector's constructor: about 2.2 MB for 36h11 and five radii, some 6 ms here, most of
// it the first touch of that memory); immutable, so shared by every thread.
class DefocusModels {
 public:
  DefocusModels() = default;
  // For every distinct payload width among those of `families` the reading tries (min_family_hamming)
  // and every radius of `opt`.
  DefocusModels(std::span<const TagFamily> families, const DefocusReadOptions& opt);

  struct Radius {
    double rho = 0;
    // One sample per cell: the solution [a, b, b p_0 .. b p_{d^2-1}] = solve * samples, and the
    // kernel over the padded grid (rows: samples, columns: (d + 6)^2 cells) for the residual.
    Eigen::MatrixXd solve, kernel;
    // samples_per_cell^2 samples per cell: the same two.
    Eigen::MatrixXd fine_solve, fine_kernel;
  };
  struct Width {
    int d = 0;
    std::vector<Radius> radii;
  };
  const Width* width(int d) const;
  int samples_per_cell() const { return m_; }

 private:
  std::vector<Width> widths_;
  int m_ = 1;
};

// Every quad whose outcome is kNotDecoded, tried as above; the new detections, in quad order. A quad
// decoded here gets its outcome updated (kDecoded, family, id, hamming, margin). `quads` and
// `outcomes` are parallel; a size mismatch finds nothing. `decoded`: the tags found so far.
std::vector<Detection> read_defocused_quads(const ImageF& gray, const DefocusModels& models,
                                            std::span<const Quad> quads, std::span<QuadOutcome> outcomes,
                                            std::span<const Detection> decoded, std::span<const TagFamily> families,
                                            int max_hamming, bool hamming_by_family, const DefocusReadOptions& opt);

namespace detail {
// The fraction of a disk of radius rho (cells) centred at (x, y) (cell units of a grid of g x g
// cells, cell (r, c) covering [c, c + 1) x [r, r + 1)) on each cell, row-major; cells past the grid's
// edge count for the edge cell. rho 0: all of it on the cell holding (x, y). Sums to 1.
std::vector<double> disk_cell_fractions(double x, double y, double rho, int g);
}  // namespace detail

}  // namespace tagbench
