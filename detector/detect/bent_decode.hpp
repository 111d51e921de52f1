#pragma once
// Beyond the paper: a second chance for a tag folded along a centre line (a bent sticker). Such a
// tag is two planes meeting at the fold: no homography maps it, and the flat homography reads the
// payload cells of each half at the wrong places (raytrace conditions, bent 30 and 40 degrees: the
// misses were payload misreads). For a quad that was read but decoded by no family (QuadOutcome
// kNotDecoded), the border is measured (border_kink.hpp); when a side is bent by at least min_kink_px
// (only one side of the fold's pair need be: seen obliquely, the other can look nearly straight), the
// tag is taken as folded across the pair whose more bent side bends more, along its centre line. Each
// half gets its own homography from its corners (the quad's corners re-located on the sides' broken
// lines, and the two points where the fold crosses that pair), and the payload is read through the
// two (payload_area.hpp, TagToImage) and decoded as decode_quads does (same bits corrected, family order
// and tie-break). Flat tags are decoded before this runs and a quad whose sides are straight is never
// re-read: it costs nothing on them and adds no reading of a quad that does not look folded. A fold
// off the centre line is not modelled.
//
// A detection found here has the re-located corners (TL, TR, BR, BL of the printed tag, as
// decode_quads.hpp), the flat homography of those corners (what the pose and the rest of the
// pipeline use) and the decision margin of the folded reading.
#include <span>
#include <vector>

#include "../codes/tag_family.hpp"
#include "border_kink.hpp"
#include "payload_area.hpp"
#include "payload_decode.hpp"
#include "quad_search.hpp"

namespace tagbench {

struct Detection;   // detector.hpp
struct QuadOutcome;  // detector.hpp

struct BentReadOptions {
  bool enabled = true;        // default profile on; DetectorOptions::paper(): off
  double min_kink_px = 0.75;  // one side of the folded pair bent by at least this (|SideKink::kink_px|), px
  BorderKinkOptions kink;     // the measurement; cells_across is set per payload width
  // A quick look first, for speed (most quads that reach here, on natural images, are not tags): the
  // border measured at precheck_samples points per side with the fold at the middle; the full
  // measurement only when a side's kink there is at least precheck_fraction x min_kink_px.
  int precheck_samples = 4;
  double precheck_fraction = 0.5;
  // Quads whose shortest side is under this are not re-read (px). A fold's kink on a small tag is lost
  // in noise and JPEG, and on natural images the many small undecoded quads made the second chance
  // the largest cost at half resolution (realistic set, tagbench-half / libapriltag d2 0.81 -> 1.17).
  double min_side_px = 32;
};

// Every quad whose outcome is kNotDecoded re-read as a folded tag (above); the new detections, in
// quad order. `outcomes` has one entry per quad (decode_quads' `outcomes`); a quad decoded here gets
// its entry updated (kDecoded, family, id, hamming, margin). `gray` is the unblurred image (the border
// is measured there), `decode_image` the one payloads are read from (decode_quads.hpp).
std::vector<Detection> decode_bent_quads(const ImageF& gray, const ImageF& decode_image, std::span<const Quad> quads,
                                         std::span<QuadOutcome> outcomes, std::span<const TagFamily> families,
                                         int max_hamming, bool hamming_by_family, const PayloadAreaOptions& area,
                                         double min_contrast, const BentReadOptions& opt);

}  // namespace tagbench
