#pragma once
// The model of photometric_refine.hpp evaluated over all of a tag's pixels at once: the Huber cost and
// the weighted Gauss-Newton normal equations at one parameter vector. Internal to the detector.
//
// Speed: the per-pixel work (homography, blurred pattern, Jacobian) runs in single precision over
// arrays (Eigen's vectorised packets, 4 pixels per SSE instruction, exp included); only the sums
// (J^T W J, J^T W r, the cost) are formed in double. Single precision is ample here: intensities
// are 8-bit quantised (a step of 0.004), tag coordinates stay within [-1.2, 1.2] (a float step
// there is 1e-7 tag units, 1e-5 px on a 100 px tag).
//
// Units and conventions as photometric_refine.hpp: parameters g11 g12 g13 g21 g22 g23 g31 g32
// (G: normalised image coordinates -> tag square, G33 = 1), a0 a1 a2 (black level, affine in the
// normalised coordinates), b0 b1 b2 (contrast, likewise), sigma (blur, pixels).
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "../codes/tag_layout.hpp"

namespace tagbench::detail {

constexpr int kPhotometricParams = 15;
constexpr int kPhotometricSigma = 14;
using PhotometricVec = Eigen::Matrix<double, kPhotometricParams, 1>;
using PhotometricMat = Eigen::Matrix<double, kPhotometricParams, kPhotometricParams>;

// The printed cells padded by one white cell all round (past the white ring the model assumes
// white); for every grid cell (iy, ix), ix and iy in -1..n, the 3x3 neighbourhood as 9 bits (bit
// 3 j + i: cell (iy - 1 + j, ix - 1 + i), clamped into -1..n, is white).
struct PhotometricPattern {
  explicit PhotometricPattern(const TagCells& c);
  int n;
  double cell;  // tag units per cell, 2 / (d + 2)
  std::vector<std::uint8_t> padded;       // (n + 2)^2, index (iy + 1) (n + 2) + ix + 1
  std::vector<std::uint16_t> neighbours;  // same indexing
  std::vector<std::array<float, 9>> neighbour_weights;  // the same bits as 0/1 floats (the model's per-pixel gather)
  // Grid column/row of tag coordinate u (the black square's left edge is grid line 1), clamped to -1..n.
  // Truncation after a positive shift is floor() without the library call.
  int index(double u) const { return std::clamp(static_cast<int>((u + 1) / cell + 64) - 63, -1, n); }
  double line(int k) const { return -1 + (k - 1) * cell; }  // tag coordinate of grid line k
  bool white(int iy, int ix) const {                        // indices clamped into -1..n
    ix = std::clamp(ix, -1, n), iy = std::clamp(iy, -1, n);
    return padded[static_cast<std::size_t>((iy + 1) * (n + 2) + ix + 1)] != 0;
  }
};

// The pixels the fit uses: normalised image coordinates and intensity, one entry each.
struct PhotometricSamples {
  std::vector<float> xn, yn, value;
  void clear() { xn.clear(), yn.clear(), value.clear(); }
  std::size_t size() const { return xn.size(); }
};

// Per-pixel arrays kept from call to call (a tag's passes reuse them).
struct PhotometricScratch {
  PhotometricScratch();
  ~PhotometricScratch();
  struct Impl;                     // the per-pixel intermediates (photometric_model.cpp)
  std::unique_ptr<Impl> impl;
  Eigen::Matrix<float, Eigen::Dynamic, kPhotometricParams> J;  // weighted Jacobian, a column per parameter
  Eigen::VectorXf rw;              // weighted residuals
};

// out[a * cols + c] = the dot product of columns a and c (c <= a) of the m x cols column-major block
// at `data` (column k at data + k * stride), each summed exactly as Eigen's VectorXf dot sums it
// (SSE: two packet accumulators over pairs of packets, joined, a last packet, the horizontal sum,
// then the remaining coefficients in order), so the same floats; several columns at a time, which
// loads each packet of column a once for up to four dot products. The rest of `out` is left alone.
void lower_column_dots(const float* data, Eigen::Index stride, Eigen::Index m, int cols, float* out);

// Huber cost (threshold `huber`, intensity units) at `p`, and J^T W J, J^T W r with the IRLS weights;
// `scale` is pixels per normalised unit. INFINITY (JtJ, Jtr unspecified) when a pixel maps behind the view.
// column_dots: J^T W J's blocks as column dot products instead of Eigen's rank update (the same sums,
// rounded differently: PhotometricRefineOptions::column_dot_sums).
double photometric_normal_equations(const PhotometricPattern& pat, const PhotometricSamples& px, double scale,
                                    const PhotometricVec& p, double huber, PhotometricMat& JtJ, PhotometricVec& Jtr,
                                    PhotometricScratch& s, bool column_dots = false);

}  // namespace tagbench::detail
