#pragma once
// Rectangle-covering complexity of a payload (paper section V-A; docs/paper-to-code.md section 2).
//
// The number of rectangles a greedy painter needs to reproduce the d x d pattern: every cell starts
// unpainted (wrong); each step paints the rectangle and colour that gains the most right cells
// (cells that become right minus cells that become wrong), the first strictly best in the loop
// order y0, y1 >= y0, x0, x1 >= x0, colour 0 then 1. Ties are broken by that order, so the count
// (and hence which codes the generator accepts) matches the original generator bit for bit.
//
// Orientation: the painter's cell (y, x) is bit y*d + x of the word (LSB first), as in the original.
#include "codes/bits.hpp"

namespace tagbench {

// Full complexity of word v with payload width d (2 <= d <= kMaxPayloadWidth).
int rectangle_complexity(Code v, int d);

// True when rectangle_complexity(v, d) >= at_least; stops painting as soon as that is certain.
bool complexity_at_least(Code v, int d, int at_least);

}  // namespace tagbench
