#pragma once
// Beyond the paper: reading the payload from each cell's area, with optional sharpening, for small
// tags. The paper (payload_decode.hpp) samples one point per cell; with 1.5-3 px cells, noise, JPEG
// blocks and a corner error of a few tenths of a pixel, one bilinear sample often lands on the
// neighbouring cell's side of a blurred step. Here:
//   - every cell of the (d+4) x (d+4) grid (white ring, black ring, payload; layout and tag
//     coordinates as in payload_decode.hpp) is the mean of k x k bilinear samples spread over the
//     central `sample_extent` of the cell (fractions of the cell's width, in tag coordinates, mapped
//     through H), which averages noise without reaching into the neighbours;
//   - the white and black ring cells train the paper's two models I = A x + B y + C x y + D (fit on
//     the cell means; fewer than 6 cells: a constant);
//   - optionally each payload cell is sharpened (more for cells under small_cell_px) against its
//     four neighbours, v' = v + s (4 v - sum of
//     neighbours) (a discrete Laplacian on the cell grid, as AprilTag 3's decode_sharpening), which
//     undoes part of the blur that spreads a cell into its neighbours when cells are 1-2 px;
//   - a payload cell is 1 when v' exceeds the mean of the two models there.
// Margin and contrast are defined as in PayloadReading (payload_decode.hpp), on the sharpened values.
#include <functional>
#include <optional>

#include <Eigen/Core>

#include "image.hpp"
#include "payload_decode.hpp"

namespace tagbench {

// Beyond AprilTag 2/3, measured and left off (issue 17, docs/default-profile.md session 26): a
// second reading of a quad whose first reading decoded nothing, its payload cells judged against
// their own two levels instead of the rings' models. On a 20-24 px tag printed on a card darker than
// the paper, the 1-cell white ring (2-3 px) is blurred into the card and the black border, so the
// white model says little (or less than the black one: no reading at all), while the payload's cells
// still hold both levels. The threshold is the 2-means split of the (sharpened) payload values; the
// reading is kept only when nearly the whole black ring is below it (a texture quad's "ring" is
// not), and is decoded with spare_bits fewer bits corrected than the family's own (decode_quads.hpp).
// At the true corners of the realistic set's 20-24 px tags it reads 5 more of 188 within 3 bits than
// the ring models alone; as a detector stage it found none of them (their quads are not that close).
struct SelfThresholdOptions {
  bool enabled = false;               // off in every profile (variant key `self`)
  double max_light_black_ring = 0.1;  // black-ring cells above the threshold at most this fraction, [0, 1]
  int spare_bits = 0;                 // bits corrected = the family's own minus this, >= 0
  int min_family_hamming = 0;         // only families of at least this minimum distance, >= 0
};

struct PayloadAreaOptions {
  int samples_per_side = 3;     // k: k x k samples per cell (1 = the cell centre only)
  double sample_extent = 0.3;   // the samples span this fraction of a cell's width, centred (wider
                                // averages more of the blurred step between cells: worse when blurred)
  double sharpening = 0.5;      // s above; 0 = off (AprilTag 3's default decode_sharpening is 0.25;
                                // on 12-18 px blurred tags 0.5 corrects about half the bits 0.25 leaves)
  double min_contrast = 0.02;   // white minus black model at the tag centre, [0, 1] intensities
  // Cells narrower than small_cell_px (the black square's mean side in pixels over d + 2) are
  // sharpened by small_cell_sharpening instead: at 1-1.2 px a cell's value is mostly its neighbours'
  // blur, and 0.75 recovers bits 0.5 leaves (distance sweep beyond 40 m, 9 px tags); larger cells,
  // where stronger sharpening would amplify noise and JPEG blocks, keep `sharpening`. 0 = off.
  double small_cell_px = 1.2;
  double small_cell_sharpening = 0.75;
  SelfThresholdOptions self_threshold;  // used by decode_quads.hpp only, not by read_payload_area
};

// Reads a d x d payload through H (tag square [-1,1]^2 -> image); nullopt when a payload cell's
// sample leaves the image, the border gives no model, or the contrast is below min_contrast.
// Bits in AprilTag 1 order as seen through the quad (as read_payload).
std::optional<PayloadReading> read_payload_area(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                                const PayloadAreaOptions& opt = {}, bool keep_points = false);

// The second reading above (SelfThresholdOptions): the same cells and sharpening as
// read_payload_area, each payload cell 1 when above the 2-means split of the payload values. nullopt
// as read_payload_area, when the payload holds one level only, when the split's two means differ
// by less than opt.min_contrast, or when more than max_light_black_ring of the black ring is above
// it. contrast: the two means' difference; margin and confidence relative to half of it. No points.
std::optional<PayloadReading> read_payload_self_threshold(const ImageF& img, const Eigen::Matrix3d& H, int d,
                                                          const PayloadAreaOptions& opt);

// The same through any map of tag coordinates ([-1,1]^2 the black square) to image pixels, e.g. a
// folded tag's two homographies (bent_decode.hpp); with the homography's map, identical to the above.
using TagToImage = std::function<Eigen::Vector2d(const Eigen::Vector2d&)>;
std::optional<PayloadReading> read_payload_area(const ImageF& img, const TagToImage& map, int d,
                                                const PayloadAreaOptions& opt = {}, bool keep_points = false);

}  // namespace tagbench
