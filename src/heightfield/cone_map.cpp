// Conservative cone maps: near gradient bounds and a far bound over a pyramid of cells
// (cone_map.h).
#include "heightfield/cone_map.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/progress.h"

namespace pgt {

namespace {

// The cells of a map with their extents in texel-centre lattice units, and each cell's
// exact range and steepest gradient of e.
struct Cells {
    int W = 0, H = 0, cx = 0, cy = 0;
    bool repeat = true;
    double sign = 1;
    std::vector<double> lo, hi, grad;  // per cell

    Cells(const Texture& t, bool inverted)
        : W(t.width), H(t.height), repeat(t.address == Address::Repeat), sign(inverted ? -1 : 1) {
        cx = repeat ? W : std::max(W - 1, 1);
        cy = repeat ? H : std::max(H - 1, 1);
        lo.resize(size_t(cx) * cy);
        hi.resize(lo.size());
        grad.resize(lo.size());
        for (int j = 0; j < cy; ++j)
            for (int i = 0; i < cx; ++i) {
                const int i1 = repeat ? (i + 1) % W : std::min(i + 1, W - 1);
                const int j1 = repeat ? (j + 1) % H : std::min(j + 1, H - 1);
                const double a = sign * t.texel(i, j), b = sign * t.texel(i1, j);
                const double c = sign * t.texel(i, j1), d = sign * t.texel(i1, j1);
                const size_t k = size_t(j) * cx + i;
                lo[k] = std::min({a, b, c, d});
                hi[k] = std::max({a, b, c, d});
                // At its corners: (d/dx, d/dy) per UV unit (x = u W, y = v H).
                double g = 0;
                for (auto [gx, gy] :
                     {std::pair{b - a, c - a}, {b - a, d - b}, {d - c, c - a}, {d - c, d - b}})
                    g = std::max(g, std::hypot(gx * W, gy * H));
                grad[k] = g;
            }
    }

    // Lattice extent of cells [i0, i1) along an axis of `texels` and `cells`.
    void extent(int i0, int i1, int texels, int cells, double& a, double& b) const {
        a = i0;
        b = i1;
        if (!repeat) {
            if (i0 == 0) a = -0.5;
            if (i1 >= cells) b = texels - 0.5;
        }
    }

    // The gap between lattice intervals [a0, a1] and [b0, b1] (on a circle of `length`
    // when the map repeats).
    double gap(double a0, double a1, double b0, double b1, double length) const {
        if (!repeat) return std::max({0.0, b0 - a1, a0 - b1});
        const double la = a1 - a0, lb = b1 - b0;
        if (la + lb >= length) return 0;
        auto mod = [&](double x) {
            x = std::fmod(x, length);
            return x < 0 ? x + length : x;
        };
        const double right = mod(b0 - a1), left = mod(a0 - b1);
        if (right + left + la + lb > length + 0.25) return 0;  // they overlap
        return std::min(right, left);
    }
};

// The steepest gradient over each cell's block: a sliding maximum along x, then along y.
std::vector<double> blockGradient(const Cells& g) {
    std::vector<double> rows(g.grad.size()), out(g.grad.size());
    auto slide = [&](const std::vector<double>& in, std::vector<double>& to, bool alongX) {
        const int n = alongX ? g.cx : g.cy, m = alongX ? g.cy : g.cx;
        tbb::parallel_for(0, m, [&](int line) {
            for (int k = 0; k < n; ++k) {
                double best = 0;
                for (int d = -kConeBlock; d <= kConeBlock; ++d) {
                    int q = k + d;
                    if (g.repeat)
                        q = ((q % n) + n) % n;
                    else if (q < 0 || q >= n)
                        continue;
                    const size_t at = alongX ? size_t(line) * g.cx + q : size_t(q) * g.cx + line;
                    best = std::max(best, in[at]);
                }
                (alongX ? to[size_t(line) * g.cx + k] : to[size_t(k) * g.cx + line]) = best;
            }
        });
    };
    slide(g.grad, rows, true);
    slide(rows, out, false);
    return out;
}

// The highest e over aligned blocks of cells: level k, node (i, j) holds cells [i 2^k,
// (i + 1) 2^k) x [j 2^k, (j + 1) 2^k) (those that exist). Built from the exact cell ranges, so
// a repeating map's wrapping cells are included as they are.
std::vector<std::vector<double>> highPyramid(const Cells& g, int levels) {
    std::vector<std::vector<double>> up(static_cast<size_t>(levels));
    up[0] = g.hi;
    int w = g.cx, h = g.cy;
    for (int k = 1; k < levels; ++k) {
        const int cw = (w + 1) / 2, ch = (h + 1) / 2;
        up[size_t(k)].assign(size_t(cw) * ch, -INFINITY);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                double& to = up[size_t(k)][size_t(j / 2) * cw + i / 2];
                to = std::max(to, up[size_t(k - 1)][size_t(j) * w + i]);
            }
        w = cw, h = ch;
    }
    return up;
}

}  // namespace

ConeMap buildConeMap(const Texture& t, bool inverted) {
    PGT_CHECK(t.width > 0 && t.height > 0);
    const Cells g(t, inverted);
    const std::vector<double> near = blockGradient(g);
    ConeMap m;
    m.width = t.width;
    m.height = t.height;
    m.cellsX = g.cx;
    m.cellsY = g.cy;
    m.address = t.address;
    m.inverted = inverted;
    m.top = float(*std::max_element(g.hi.begin(), g.hi.end()));  // e of a texel: exact
    m.ratio.resize(size_t(g.cx) * g.cy);
    const double delta = kConeBlock * std::min(1.0 / g.W, 1.0 / g.H);
    int levels = 1;
    while ((1 << (levels - 1)) < std::max(g.cx, g.cy)) ++levels;
    const std::vector<std::vector<double>> up = highPyramid(g, levels);
    Progress progress("cone map " + std::to_string(t.width) + "x" + std::to_string(t.height), g.cy);
    tbb::parallel_for(0, g.cy, [&](int j) {
        throwIfCancelled();
        for (int i = 0; i < g.cx; ++i) {
            const size_t k = size_t(j) * g.cx + i;
            double ca0, ca1, cb0, cb1;
            g.extent(i, i + 1, g.W, g.cx, ca0, ca1);
            g.extent(j, j + 1, g.H, g.cy, cb0, cb1);
            double best = near[k] > 0 ? std::min(1.0 / near[k], kConeRatioCap) : kConeRatioCap;
            // Each cell R is counted once, through its ancestor at the level where R's and
            // C's parents first touch (coneLevelUsed): a few dozen nodes a level.
            for (int level = 0; level < levels; ++level) {
                const int n = 1 << level, w = (g.cx + n - 1) / n, h = (g.cy + n - 1) / n;
                const int pi = i >> (level + 1), pj = j >> (level + 1);
                for (int y = std::max(2 * pj - 2, 0); y < std::min(2 * pj + 4, h); ++y)
                    for (int x = std::max(2 * pi - 2, 0); x < std::min(2 * pi + 4, w); ++x) {
                        if (!coneLevelUsed(i, j, x, y, level, levels)) continue;
                        const double top = up[size_t(level)][size_t(y) * w + x];
                        if (!(top > g.lo[k])) continue;
                        double a0, a1, b0, b1;
                        g.extent(x * n, std::min(x * n + n, g.cx), g.W, g.cx, a0, a1);
                        g.extent(y * n, std::min(y * n + n, g.cy), g.H, g.cy, b0, b1);
                        const double d = std::hypot(g.gap(ca0, ca1, a0, a1, g.W) / g.W,
                                                    g.gap(cb0, cb1, b0, b1, g.H) / g.H);
                        best = std::min(best, std::max(d, delta) / (top - g.lo[k]));
                    }
            }
            m.ratio[k] = coneRatioBelow(best);
        }
        progress.add(1);
    });
    return m;
}

}  // namespace pgt
