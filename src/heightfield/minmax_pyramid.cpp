// The minimum-maximum pyramid and its conservative range queries (minmax_pyramid.h).
#include "heightfield/minmax_pyramid.h"

#include <algorithm>

#include "core/error.h"

namespace pgt {

MinMaxPyramid buildMinMaxPyramid(const Texture& t) {
    PGT_CHECK(t.width > 0 && t.height > 0);
    MinMaxPyramid p;
    p.width = t.width;
    p.height = t.height;
    p.address = t.address;
    MinMaxPyramid::Level l0;
    l0.w = t.width;
    l0.h = t.height;
    l0.lo.resize(size_t(l0.w) * l0.h);
    l0.hi.resize(l0.lo.size());
    for (int j = 0; j < l0.h; ++j) {
        const int j1 = std::min(j + 1, t.height - 1);
        for (int i = 0; i < l0.w; ++i) {
            const int i1 = std::min(i + 1, t.width - 1);
            const float a = t.texel(i, j), b = t.texel(i1, j), c = t.texel(i, j1),
                        d = t.texel(i1, j1);
            l0.lo[size_t(j) * l0.w + i] = std::min({a, b, c, d});
            l0.hi[size_t(j) * l0.w + i] = std::max({a, b, c, d});
        }
    }
    p.levels.push_back(std::move(l0));
    // Level k + 1 has ((W - 1) >> (k + 1)) + 1 nodes a row: node i joins nodes 2i and 2i + 1.
    for (int k = 0; p.levels.back().w > 1 || p.levels.back().h > 1; ++k) {
        const MinMaxPyramid::Level& f = p.levels.back();
        MinMaxPyramid::Level c;
        c.w = ((t.width - 1) >> (k + 1)) + 1;
        c.h = ((t.height - 1) >> (k + 1)) + 1;
        c.lo.resize(size_t(c.w) * c.h);
        c.hi.resize(c.lo.size());
        for (int j = 0; j < c.h; ++j)
            for (int i = 0; i < c.w; ++i) {
                float lo = INFINITY, hi = -INFINITY;
                for (int dj = 0; dj < 2; ++dj)
                    for (int di = 0; di < 2; ++di) {
                        const int x = 2 * i + di, y = 2 * j + dj;
                        if (x >= f.w || y >= f.h) continue;
                        lo = std::min(lo, f.lo[size_t(y) * f.w + x]);
                        hi = std::max(hi, f.hi[size_t(y) * f.w + x]);
                    }
                c.lo[size_t(j) * c.w + i] = lo;
                c.hi[size_t(j) * c.w + i] = hi;
            }
        p.levels.push_back(std::move(c));
    }
    p.lo = p.levels.back().lo[0];
    p.hi = p.levels.back().hi[0];
    return p;
}

namespace {

struct TexelRange {
    int64_t a, b;  // inclusive, within [0, n - 1]
};

// The texels lattice corners [x0, x0 + n] map to (one or two ranges).
int mapRange(int64_t x0, int64_t n, int size, Address address, TexelRange out[2]) {
    if (address == Address::Clamp) {
        out[0] = {std::clamp<int64_t>(x0, 0, size - 1), std::clamp<int64_t>(x0 + n, 0, size - 1)};
        return 1;
    }
    if (n + 1 >= size) {
        out[0] = {0, size - 1};
        return 1;
    }
    int64_t a = x0 % size;
    if (a < 0) a += size;
    const int64_t b = a + n;
    if (b <= size - 1) {
        out[0] = {a, b};
        return 1;
    }
    out[0] = {a, size - 1};
    out[1] = {0, b - size};
    return 2;
}

// The level whose nodes cover a range of `span` texels in at most two nodes an axis.
int levelFor(int64_t span, int top) {
    int k = 0;
    while (k < top && (int64_t(1) << k) < span) ++k;
    return k;
}

}  // namespace

void latticeBounds(const MinMaxPyramid& p, int64_t x0, int64_t y0, int64_t n, float& lo, float& hi,
                   int& reads) {
    TexelRange xs[2], ys[2];
    const int nx = mapRange(x0, n, p.width, p.address, xs);
    const int ny = mapRange(y0, n, p.height, p.address, ys);
    lo = INFINITY;
    hi = -INFINITY;
    for (int a = 0; a < nx; ++a)
        for (int b = 0; b < ny; ++b) {
            const int k = levelFor(std::max(xs[a].b - xs[a].a, ys[b].b - ys[b].a), p.top());
            const MinMaxPyramid::Level& l = p.levels[size_t(k)];
            const int64_t size = int64_t(1) << k;
            const int64_t i0 = xs[a].a >> k, j0 = ys[b].a >> k;
            const int64_t i1 = xs[a].b <= i0 * size + size ? i0 : i0 + 1;
            const int64_t j1 = ys[b].b <= j0 * size + size ? j0 : j0 + 1;
            for (int64_t j = j0; j <= std::min<int64_t>(j1, l.h - 1); ++j)
                for (int64_t i = i0; i <= std::min<int64_t>(i1, l.w - 1); ++i) {
                    lo = std::min(lo, l.lo[size_t(j * l.w + i)]);
                    hi = std::max(hi, l.hi[size_t(j * l.w + i)]);
                    ++reads;
                }
        }
}

}  // namespace pgt
