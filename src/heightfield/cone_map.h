// Cone maps for cone step mapping (Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield
// Intersection Algorithm", 2006), built for the bilinear surface pgt samples (docs/model.md §1) so
// that a cone step never passes the first intersection. Classic cone maps bound the surface
// from texel centres only and are not conservative under bilinear filtering (Bán, Valasek et
// al., EGSR 2024); here one ratio serves every point of a cell (the square between four
// texel centres), whatever the ray's position in it.
//
// Heights are e = h (s >= 0) or e = -h (s < 0, the relief upside down), so that "up" is
// towards the eye. Cell C's ratio c (UV distance per unit of e) promises, for every x in C
// and every surface point y: e(y) - e(x) <= |y - x| / c. It is the smaller of
//  - near: 1 / G, G the steepest gradient |grad e| (UV units) over the cells within kBlock
//    cells of C (a bilinear cell is steepest at a corner); it covers y in that block, since
//    the segment x-y stays inside it;
//  - far: the minimum over all cells R of max(d(C, R), delta) / (e_max(R) - e_min(C)) where
//    e_max(R) > e_min(C), with d the UV distance between the cells (the nearest periodic
//    copies when the map repeats) and delta = kBlock * min(1/W, 1/H), the least distance
//    from C to a point outside its block.
// With a clamped map the edge cells reach to the map's border, and points beyond it see the
// border's heights (clamping is a projection, so distances only shrink: still covered).
// For speed each cell R enters the far minimum through its ancestor node in a pyramid
// of cells (the node's highest e, its distance), at the level where R's and C's parents first
// touch (coneLevelUsed): a node's bound is below every cell's in it, so this only makes c
// smaller (safer), and it visits a few dozen nodes a level: O(N^2 log N) for N^2 cells, after
// Valasek & Bán, "Quick Cone Map Generation on the GPU" (EG 2022 short papers). Ratios are
// capped at kConeRatioCap. tests/cone_test.cpp compares the build with a brute-force O(N^4)
// build of the same definition, and with the exact cell-by-cell optimum.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "heightfield/texture.h"

namespace pgt {

struct ConeMap {
    int width = 0, height = 0;   // the map's texels
    int cellsX = 0, cellsY = 0;  // repeat: W x H (the last wraps); clamp: max(W - 1, 1) x ...
    Address address = Address::Repeat;
    bool inverted = false;     // built for e = -h (s < 0)
    float top = 0;             // the highest e of the map (where the rays start)
    std::vector<float> ratio;  // per cell (relaxed: per texel), j * cellsX + i; <= kConeRatioCap
};

// The block radius of the near bound (cells).
inline constexpr int kConeBlock = 4;
// The largest ratio a cone map holds (UV per unit of height): Dummer's maps store 0..1.
inline constexpr double kConeRatioCap = 1.0;

// floor(x) wrapped into [0, n) (repeat) or clamped to it; any input, NaN included, gives one.
template <class Real>
int coneIndex(Real x, int n, Address address) {
    x = std::floor(x);
    if (!(x > Real(-1e9))) x = Real(-1e9);  // NaN and -inf too
    if (x > Real(1e9)) x = Real(1e9);
    int64_t i = int64_t(x);
    if (address == Address::Repeat) {
        i %= n;
        if (i < 0) i += n;
    } else {
        i = std::min<int64_t>(std::max<int64_t>(i, 0), n - 1);
    }
    return int(i);
}

// The largest float not above x: a stored ratio never promises more than the double did.
inline float coneRatioBelow(double x) {
    if (!(x < double(FLT_MAX))) return FLT_MAX;
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, 0.0f);
    return f;
}

// The cell that holds UV point (u, v): lattice x = u W - 0.5, floored, then wrapped (repeat)
// or clamped to the cells (clamp). Any finite or infinite input gives a valid cell.
template <class Real>
int coneCell(const ConeMap& m, Real u, Real v) {
    return coneIndex(v * Real(m.height) - Real(0.5), m.cellsY, m.address) * m.cellsX +
           coneIndex(u * Real(m.width) - Real(0.5), m.cellsX, m.address);
}

// Whether cell R = (x, y)'s ancestor at `level`, node (rx, ry), stands for R in cell C = (i,
// j)'s far minimum: the lowest level at which R's and C's parents are within one node of each
// other (Chebyshev distance of node indices; every level's parents at the top).
inline bool coneLevelUsed(int i, int j, int rx, int ry, int level, int levels) {
    auto cheb = [](int ax, int ay, int bx, int by) {
        return std::max(std::abs(ax - bx), std::abs(ay - by));
    };
    const bool parentsTouch =
        level + 1 >= levels || cheb(rx >> 1, ry >> 1, i >> (level + 1), j >> (level + 1)) <= 1;
    const bool touchedBelow = level > 0 && cheb(rx, ry, i >> level, j >> level) <= 1;
    return parentsTouch && !touchedBelow;
}

// The conservative cone map of `t` (e = h, or -h when `inverted`).
ConeMap buildConeMap(const Texture& t, bool inverted);

// Relaxed cone maps (Policarpo & Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU
// Gems 3, ch. 18, §18.3): one ratio per texel T, the apex at T's centre and height e_T.
// Their definition (the book's listing 18-5): for every other texel D, the ray from above T
// at the map's top through D's surface point is followed to where it comes out of the
// surface after being inside, X; the cone must not hold X: c_T <= |X - T| / (e_X - e_T) where
// e_X > e_T. Such rays then enter the surface at most once before they reach the cone's side.
// The book searches only past D, by fixed steps; pgt follows the whole ray over the bilinear
// surface exactly (along a line a cell's patch is a quadratic, so X is a root), for texels D
// within kRelaxedRadius texels of T, and caps c_T at kRelaxedRadius texels / (top - e_T),
// beyond which no X can lie inside the cone. Where the conservative cone map's
// ratio (the smallest of the four cells at T) is larger, that one is kept: it has no crossing
// at all. A ratio at most kConeRatioCap.
inline constexpr int kRelaxedRadius = 8;

// The relaxed cone map of `t` for e = h (or -h when `inverted`); `conservative` is t's cone
// map for the same sign.
ConeMap buildRelaxedConeMap(const Texture& t, const ConeMap& conservative);

// The texel whose centre is nearest UV point (u, v): floor(u W), wrapped or clamped.
template <class Real>
int relaxedTexel(const ConeMap& m, Real u, Real v) {
    return coneIndex(v * Real(m.height), m.height, m.address) * m.width +
           coneIndex(u * Real(m.width), m.width, m.address);
}

}  // namespace pgt
