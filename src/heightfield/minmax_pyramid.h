// The minimum-maximum pyramid of a height map (Tevs, Ihrke, Seidel, "Maximum Mipmaps for
// Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008): node (i, j) of
// level k bounds the texels [i 2^k, i 2^k + 2^k] x [j 2^k, j 2^k + 2^k] (clamped to the map),
// one texel more than its 2^k x 2^k cells, so that it bounds the bilinear surface over them
// (docs/model.md §1: a bilinear patch lies between its corners' minimum and maximum). Built once
// per map; it does not depend on (s, b).
#pragma once

#include <cstdint>
#include <vector>

#include "heightfield/texture.h"

namespace pgt {

struct MinMaxPyramid {
    struct Level {
        int w = 0, h = 0;
        std::vector<float> lo, hi;  // j * w + i
    };
    int width = 0, height = 0;  // the map's texels
    Address address = Address::Repeat;
    std::vector<Level> levels;  // levels[0]: the cells; the last one is 1 x 1
    float lo = 0, hi = 0;       // the whole map's

    int top() const { return int(levels.size()) - 1; }
};

MinMaxPyramid buildMinMaxPyramid(const Texture& t);

// Bounds of the height over lattice cells [x0, x0 + n) x [y0, y0 + n) (cell (x, y) spans
// texel coordinates [x, x + 1] x [y, y + 1] with centres at integers, docs/model.md §1; any
// integers, the address mode maps them): lo <= h <= hi there. Conservative (a node may
// cover a little more) and exact for a cell or an aligned node of a power-of-two map.
// `reads` counts the pyramid nodes read.
void latticeBounds(const MinMaxPyramid& p, int64_t x0, int64_t y0, int64_t n, float& lo, float& hi,
                   int& reads);

}  // namespace pgt
