#pragma once
// After decoding (stage 6, paper section III-B's end; the rule: docs/paper-to-code.md section 1):
// one detection per physical tag (the paper's duplicates; beyond it, two ids over one quad), then the
// minimum decision margin (beyond the paper).
#include <vector>

#include "detect/detector.hpp"

namespace tagbench {

// Two detections are duplicates when they have the same family and id and their centres are closer
// than 1/16 of the two quads' summed perimeters (the perimeter of the corners, not the observed
// one). Of two duplicates the one with the lower hamming is kept, then, on equal hamming, the one
// with the strictly longer observed_perimeter; on a full tie the earlier one stays.
//
// Exactly how (a single pass, so the result depends on the input order): each detection d, in
// input order, is compared with the kept ones in order, and only the first kept one it duplicates
// matters: if d is better it replaces that one in place, otherwise d is dropped; if it duplicates
// none, d is appended. So d never displaces two kept detections, and kept detections are never
// merged with each other, even when a replacement moves one close to another.
std::vector<Detection> suppress_duplicates(std::vector<Detection> detections);

// Beyond the paper (DetectorOptions::suppress_overlaps; default profile): two detections of different
// ids (or families) over the same quad are one physical tag read two ways, one of them wrong (16h5's
// close codes, read through a quad a few pixels off). They overlap when each one's centre lies inside
// the other's corners and their perimeters differ by less than max_perimeter_ratio (so a small tag
// nested in a large one's hollow is left alone). The readings are taken best first (fewer bits
// corrected, then the higher decision_margin, then input order) and each is kept when it overlaps no
// reading kept before it; the kept ones are returned in input order. No two kept ones overlap.
std::vector<Detection> suppress_overlaps(std::vector<Detection> detections, double max_perimeter_ratio = 1.5);

// Removes the detections whose decision_margin is below min_decision_margin (order kept).
void drop_below_margin(std::vector<Detection>& detections, double min_decision_margin);

}  // namespace tagbench
