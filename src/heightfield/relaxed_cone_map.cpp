// Relaxed cone maps over the bilinear surface (cone_map.h, buildRelaxedConeMap).
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "heightfield/cone_map.h"

namespace pgt {

namespace {

// e = sign * h over the bilinear surface, in texel-centre lattice units (x = u W - 0.5): the
// texels (negated where the map is inverted: exact in float) with a border of kPad texels
// wrapped (repeat) or repeated (clamp), so that a walk's lookups need no addressing; the same
// values texelPair's addressing gives.
struct Surface {
    static constexpr int kPad = kRelaxedRadius + 4;  // a walk stays within kRelaxedRadius + 1
    int width = 0, height = 0, stride = 0;
    std::vector<float> e;

    Surface(const Texture& t, double sign)
        : width(t.width), height(t.height), stride(t.width + 2 * kPad) {
        e.resize(size_t(stride) * size_t(t.height + 2 * kPad));
        for (int j = -kPad; j < t.height + kPad; ++j)
            for (int i = -kPad; i < t.width + kPad; ++i)
                at(i, j) = float(sign) * t.texel(coneIndex(double(i), t.width, t.address),
                                                 coneIndex(double(j), t.height, t.address));
    }
    float& at(int i, int j) { return e[size_t(j + kPad) * size_t(stride) + size_t(i + kPad)]; }
    double at(int i, int j) const {
        return e[size_t(j + kPad) * size_t(stride) + size_t(i + kPad)];
    }

    // The patch of the cell holding lattice point (x, y), along the line (x, y) + (dx, dy) s:
    // e = h0 + h1 s + h2 s^2 (docs/model.md §1).
    void along(double x, double y, double dx, double dy, double& h0, double& h1, double& h2) const {
        const double flx = std::floor(x), fly = std::floor(y), fx = x - flx, fy = y - fly;
        const int i = int(flx), j = int(fly);
        PGT_CHECK(i >= -kPad && i + 1 < width + kPad && j >= -kPad && j + 1 < height + kPad);
        const float* row = &e[size_t(j + kPad) * size_t(stride) + size_t(i + kPad)];
        const double a = row[0], b = row[1], c = row[size_t(stride)], d = row[size_t(stride) + 1];
        const double ee = b - a, f = c - a, g = a - b - c + d;
        h0 = a + ee * fx + f * fy + g * fx * fy;
        h1 = ee * dx + f * dy + g * (fx * dy + fy * dx);
        h2 = g * dx * dy;
    }
};

// Along the ray x(s) = p + d s (lattice units), e(s) = e0 - s / slope, from s = 0 to sMax:
// the first s where the ray comes out of the surface (above it after an interval below it;
// touching is not entering), or -1. Cell by cell the gap ray - surface is a quadratic; between its
// roots (and the cell's ends) its sign is that at the middle.
double firstExit(const Surface& surf, double px, double py, double dx, double dy, double e0,
                 double slope, double sMax) {
    double s = 0;
    bool inside = false;
    for (int guard = 0; s < sMax && guard < 4096; ++guard) {
        const double x = px + dx * s, y = py + dy * s;
        // The next cell edge along the line (a tiny step past it keeps the floor stable).
        auto edge = [](double v, double dv) {
            if (dv > 0) return (std::floor(v) + 1 - v) / dv;
            if (dv < 0) return (std::ceil(v) - 1 - v) / dv;
            return double(INFINITY);
        };
        double len = std::min({edge(x, dx), edge(y, dy), sMax - s});
        if (!(len > 1e-12)) len = 1e-12;
        const double mx = x + dx * len * 0.5, my = y + dy * len * 0.5;  // the cell's inside
        double h0, h1, h2;
        surf.along(mx, my, dx, dy, h0, h1, h2);
        // gap(sigma) = e(s + len/2 + sigma) - surface, sigma in [-len/2, len/2].
        const double C = e0 - (s + len * 0.5) / slope - h0, B = -1 / slope - h1, A = -h2;
        double cuts[4] = {-len * 0.5, len * 0.5, len * 0.5, len * 0.5};
        int n = 1;
        if (A != 0) {
            const double disc = B * B - 4 * A * C;
            if (disc >= 0) {
                const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
                for (double r : {q / A, q != 0 ? C / q : double(INFINITY)})
                    if (r > -len * 0.5 && r < len * 0.5) cuts[n++] = r;
            }
        } else if (B != 0) {
            const double r = -C / B;
            if (r > -len * 0.5 && r < len * 0.5) cuts[n++] = r;
        }
        for (int a = 1; a < n; ++a)  // at most three: an insertion sort
            for (int b = a; b > 0 && cuts[b] < cuts[b - 1]; --b) std::swap(cuts[b], cuts[b - 1]);
        cuts[n] = len * 0.5;
        for (int k = 0; k < n; ++k) {
            // Within rounding of the surface (a ray through a texel's surface point grazes it
            // there) is neither in nor out.
            const double mid = 0.5 * (cuts[k] + cuts[k + 1]), gap = C + (B + A * mid) * mid;
            if (gap > 1e-12 && inside) return s + len * 0.5 + cuts[k];
            inside = inside || gap < -1e-12;
        }
        s += len;
    }
    return -1;
}

}  // namespace

ConeMap buildRelaxedConeMap(const Texture& t, const ConeMap& conservative) {
    PGT_CHECK(t.width == conservative.width && t.height == conservative.height);
    ConeMap m = conservative;
    m.cellsX = t.width;  // one ratio per texel
    m.cellsY = t.height;
    m.ratio.assign(size_t(t.width) * t.height, 0.0f);
    const double sign = conservative.inverted ? -1.0 : 1.0;
    const Surface surf(t, sign);
    const double W = t.width, H = t.height, top = conservative.top;
    const double reach = kRelaxedRadius * std::min(1 / W, 1 / H);  // UV
    // The texels D around T, nearest first: near exits narrow the cone early, and a narrower
    // cone shortens every later ray's walk.
    struct Neighbour {
        int di, dj;
        double rho;  // UV from T to D
    };
    std::vector<Neighbour> around;
    for (int dj = -kRelaxedRadius; dj <= kRelaxedRadius; ++dj)
        for (int di = -kRelaxedRadius; di <= kRelaxedRadius; ++di)
            if (di != 0 || dj != 0) around.push_back({di, dj, std::hypot(di / W, dj / H)});
    std::stable_sort(around.begin(), around.end(),
                     [](const Neighbour& a, const Neighbour& b) { return a.rho < b.rho; });
    // Minutes at 2048^2 and beyond (docs/performance.md): progress, and Ctrl-C stops it.
    Progress progress(
        "relaxed cone map " + std::to_string(t.width) + "x" + std::to_string(t.height), t.height);
    tbb::parallel_for(0, t.height, [&](int j) {
        throwIfCancelled();
        for (int i = 0; i < t.width; ++i) {
            const double eT = surf.at(i, j);
            // Apex at T: the conservative ratio of the cells around it holds too.
            double safe = kConeRatioCap;
            for (int cj : {j - 1, j})
                for (int ci : {i - 1, i}) {
                    const int k = coneCell(conservative, (ci + 1) / W, (cj + 1) / H);
                    safe = std::min(safe, double(conservative.ratio[size_t(k)]));
                }
            double best = top > eT ? std::min(kConeRatioCap, reach / (top - eT)) : kConeRatioCap;
            for (const auto& [di, dj, rho] : around) {
                const double eD = surf.at(i + di, j + dj);
                if (!(top > eD)) continue;
                // The ray from (T, top) through (D, eD), in lattice steps of one (di, dj),
                // to where it meets the side of the cone as it stands (an exit beyond
                // could not narrow it; nor beyond the reach of the cap).
                const double slope = 1 / (top - eD);  // (di, dj) steps per unit of e
                const double side = (top - eT) / ((top - eD) / rho + 1 / best);  // UV
                const double s =
                    firstExit(surf, i, j, di, dj, top, slope, std::min(reach, side) / rho);
                if (s < 0) continue;
                const double eX = top - s / slope;
                if (eX > eT) best = std::min(best, rho * s / (eX - eT));
            }
            m.ratio[size_t(j) * t.width + i] = coneRatioBelow(std::max(best, safe));
        }
        progress.add(1);
    });
    return m;
}

}  // namespace pgt
