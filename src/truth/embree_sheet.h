// The Embree sheet behind a TruthSurface (internal to src/truth/): the displaced base
// tessellation as Embree grid or triangle geometry, built, displaced and refit in place, with
// the ray set-up and hit-to-UV (periodic walk included) that tracing and the precision check
// share. Included by truth.cpp and precision.cpp only.
#pragma once

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "compare/statistics.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "truth/embree_device.h"
#include "truth/truth.h"

namespace pgt {

// Grids are split into blocks of at most this many segments per side; blocks share their
// boundary vertices, so the sheet stays watertight. Small blocks for two reasons, both measured
// (docs/performance.md): Embree 3.13 makes a grid geometry's primitive references in tasks of
// 1024 grids, so a sheet of fewer grids is referenced on one core (a fine truth's 4 grids of
// 1024 segments: 175 ms of its 2-core build on one core); and a hit's u, v are floats over its
// whole grid, so a 1024-segment grid rounds the hit's place in its cell to 1e-4 of a cell, a
// 16-segment one to 2e-6 (the truth's rate-vs-2x-rate uncertainty fell tenfold, p50 7.6e-6 to
// 7.3e-7 texels on a 512^2 sine frame).
constexpr int kGridBlock = 16;

struct TruthSurface::Impl {
    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    // Released here, so that a constructor stopped part-way (a cancel, an Embree error)
    // leaks neither the geometry nor the scene.
    ~Impl() {
        if (geom) rtcReleaseGeometry(geom);
        if (scene) rtcReleaseScene(scene);
    }
    std::shared_ptr<const BaseTessellation> base;
    TruthGeometry geometry;
    bool periodic = false;
    int nu = 0, nv = 0;
    Vec3d boundsLo{0}, boundsHi{0};  // of the displaced vertices, local frame
    double margin = 0;               // rays start this far before the bounds
    std::vector<RTCGrid> grids;
    std::vector<std::pair<int, int>> gridStart;  // (i0, j0) of each grid block
    RTCScene scene = nullptr;
    RTCGeometry geom = nullptr;
    Vec3f* vertices = nullptr;  // Embree's vertex buffer (owned by the geometry)
    TruthBuildStats stats;
    TruthUpdate lastUpdate = TruthUpdate::Rebuild;
    Displacement built;  // the (s, b) in Embree's vertices
    Vec3d shift{0};      // a translation of the built sheet (TruthUpdate::Translate)

    // A grid hit's cell in the lattice and the point within it. Embree 3.13 reports a grid
    // hit's u, v over the whole grid primitive (0..1 across its width x height vertices), not
    // over the cell that was hit: the cell is found here, and (u, v) made local to it.
    struct GridCell {
        int ci, cj;     // lattice cell (the block's start added)
        double fx, fy;  // within it, 0..1
    };
    GridCell gridCell(const RTCRayHit& rh) const {
        const RTCGrid& g = grids[rh.hit.primID];
        const double gx = double(rh.hit.u) * (g.width - 1), gy = double(rh.hit.v) * (g.height - 1);
        const int ci = std::min(int(gx), g.width - 2), cj = std::min(int(gy), g.height - 2);
        return {gridStart[rh.hit.primID].first + ci, gridStart[rh.hit.primID].second + cj, gx - ci,
                gy - cj};
    }

    // The candidate triangles (vertex indices) of a hit: one, or a grid cell's two.
    int candidates(const RTCRayHit& rh, uint32_t out[2][3]) const {
        if (!base->sheet.triangles.empty()) {
            const uint32_t* t = &base->sheet.triangles[size_t(rh.hit.primID) * 3];
            out[0][0] = t[0], out[0][1] = t[1], out[0][2] = t[2];
            return 1;
        }
        int ci, cj;
        if (geometry == TruthGeometry::Grid) {
            const GridCell c = gridCell(rh);
            ci = c.ci, cj = c.cj;
        } else {
            ci = int((rh.hit.primID / 2) % unsigned(nu));
            cj = int((rh.hit.primID / 2) / unsigned(nu));
        }
        uint32_t a = uint32_t(base->grid->gridIndex(ci, cj)), b = a + 1;
        uint32_t c = uint32_t(base->grid->gridIndex(ci, cj + 1)), d = c + 1;
        out[0][0] = a, out[0][1] = b, out[0][2] = c;
        out[1][0] = d, out[1][1] = c, out[1][2] = b;
        return 2;
    }

    // The vertex indices of the one triangle a hit lies on (a grid cell is split along its
    // (1,0)-(0,1) diagonal, as Embree splits a grid's quads and cellUv interpolates).
    void hitTriangle(const RTCRayHit& rh, uint32_t tri[3]) const {
        uint32_t out[2][3];
        int pick = 0;
        if (candidates(rh, out) == 2) {
            if (geometry == TruthGeometry::Grid) {
                const GridCell c = gridCell(rh);
                pick = c.fx + c.fy <= 1 ? 0 : 1;
            } else {
                pick = int(rh.hit.primID % 2);
            }
        }
        std::copy(out[pick], out[pick] + 3, tri);
    }

    // Vertex UVs interpolated over the triangle of cell (ci, cj) containing local (fx, fy):
    // the cell is split along its (1,0)-(0,1) diagonal.
    Vec2d cellUv(int ci, int cj, double fx, double fy) const {
        ci = std::clamp(ci, 0, nu - 1);
        cj = std::clamp(cj, 0, nv - 1);
        const PlaneGrid& t = *base->grid;
        // A parallelogram's UVs are affine in (i, j): both triangles of a cell interpolate
        // the same affine function, which is the corners' blend at the hit's lattice point.
        if (t.affineUv)
            return PlaneGrid::blend(t.cornerUv, (ci + t.offsetI + fx) * t.invNu,
                                    (cj + t.offsetJ + fy) * t.invNv);
        const Vec2d a = t.gridUv(ci, cj), b = t.gridUv(ci + 1, cj);
        const Vec2d c = t.gridUv(ci, cj + 1), d = t.gridUv(ci + 1, cj + 1);
        if (fx + fy <= 1) return a + (b - a) * fx + (c - a) * fy;
        return d + (c - d) * (1 - fx) + (b - d) * (1 - fy);
    }

    TruthSample hitToSample(const RTCRayHit& rh) const {
        TruthSample s;
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return s;
        s.hit = true;
        if (geometry == TruthGeometry::Grid) {
            const GridCell c = gridCell(rh);
            s.uv = cellUv(c.ci, c.cj, c.fx, c.fy);
        } else if (!base->sheet.triangles.empty()) {
            const uint32_t* t = &base->sheet.triangles[size_t(rh.hit.primID) * 3];
            double u = rh.hit.u, v = rh.hit.v;
            const std::vector<Vec2d>& uv = base->sheet.uv;
            s.uv = uv[t[0]] * (1 - u - v) + uv[t[1]] * u + uv[t[2]] * v;
        } else {
            // Two triangles per cell: 2k = (a, b, c), 2k+1 = (d, c, b); Embree's barycentrics
            // weight v1 by u and v2 by v, so in 2k+1 the cell-local point is (1 - u, 1 - v).
            int64_t cell = rh.hit.primID / 2;
            int ci = int(cell % nu), cj = int(cell / nu);
            double u = rh.hit.u, v = rh.hit.v;
            if (rh.hit.primID % 2 == 0)
                s.uv = cellUv(ci, cj, u, v);
            else
                s.uv = cellUv(ci, cj, 1 - u, 1 - v);
        }
        return s;
    }

    // One ray's walk through the relief, in the local frame: clipped to the bounds, then one
    // Embree ray per tile stretch (periodic planes) or a single one. The scalar trace and
    // the coherent tile tracer both drive it, so they differ in nothing but the Embree call.
    struct Walk {
        Vec3d o{0}, dir{0};
        double t = 0, tExit = 0;
        double leave = 0;   // this stretch's length to the tile walls (periodic)
        Vec2d uvOffset{0};  // tile offset of this stretch
        Vec3d segOrg{0};    // the ray as given to Embree for this stretch, before rounding
        int guard = 0;
        bool line = false;  // an orthographic ray: a whole line, no origin to start from
        bool done = false;
        TruthSample result;
        Vec3d ng{0};  // the hit triangle's geometric normal (unnormalised, either side)
    };

    // Clips the ray; false when it misses the relief's bounds entirely.
    bool start(const Ray& ray, Walk& w) const {
        w.o = ray.origin - base->origin - shift;  // into the built sheet's frame, in double
        w.dir = ray.dir;
        w.guard = 0;
        w.line = ray.line;
        w.done = false;
        w.result = TruthSample{};
        const double inf = std::numeric_limits<double>::infinity();
        // Parametric interval of the ray inside the bounds (x, y unbounded when periodic).
        double tEnter = ray.line ? -inf : 0.0, tExit = inf;
        for (int a = 0; a < (periodic ? 1 : 3); ++a) {
            int axis = periodic ? 2 : a;
            if (ray.dir[axis] == 0) {
                if (w.o[axis] < boundsLo[axis] || w.o[axis] > boundsHi[axis]) return false;
                continue;
            }
            const double inv = 1.0 / ray.dir[axis];
            double t0 = (boundsLo[axis] - w.o[axis]) * inv;
            double t1 = (boundsHi[axis] - w.o[axis]) * inv;
            tEnter = std::max(tEnter, std::min(t0, t1));
            tExit = std::min(tExit, std::max(t0, t1));
        }
        if (!(tEnter <= tExit) || !std::isfinite(tEnter)) return false;
        // Start a little before the bounds so the float ray begins within a box-size of the
        // hit: float error scales with |origin| + t. 1% of the box keeps it strictly outside.
        w.t = ray.line ? tEnter - margin : std::max(0.0, tEnter - margin);
        w.tExit = tExit;
        return true;
    }

    // The Embree ray of the walk's current stretch. Infinite plane: the one tile shifted
    // under the stretch, up to the tile's side walls (plus a hair, so no gap is skipped).
    void segment(Walk& w, RTCRayHit& rh) const {
        Vec3d org = w.o + w.dir * w.t;
        double tfar = std::numeric_limits<double>::infinity();
        w.uvOffset = Vec2d(0);
        if (periodic) {
            const double L = base->periodWorld, T = base->periodUv;
            double kx = std::floor((org.x + L / 2) / L), ky = std::floor((org.y + L / 2) / L);
            org = Vec3d(org.x - kx * L, org.y - ky * L, org.z);
            double leave = std::numeric_limits<double>::infinity();
            for (int a = 0; a < 2; ++a) {
                if (w.dir[a] > 0) leave = std::min(leave, (L / 2 - org[a]) / w.dir[a]);
                if (w.dir[a] < 0) leave = std::min(leave, (-L / 2 - org[a]) / w.dir[a]);
            }
            w.leave = std::max(leave, 0.0);
            w.uvOffset = Vec2d(kx * T, ky * T);
            // 1e-9 L past the tile's edge, so a hit on the edge itself is not lost between
            // two tiles (far above double rounding at the tile's scale, far below a texel).
            tfar = std::min(w.leave, w.tExit + margin - w.t) + 1e-9 * L;
        }
        w.segOrg = org;
        rh.ray.org_x = float(org.x), rh.ray.org_y = float(org.y), rh.ray.org_z = float(org.z);
        rh.ray.dir_x = float(w.dir.x), rh.ray.dir_y = float(w.dir.y), rh.ray.dir_z = float(w.dir.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::isfinite(tfar) ? float(tfar) : std::numeric_limits<float>::infinity();
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }

    // After Embree answered the stretch: a hit ends the walk; a miss moves to the next tile.
    void advance(Walk& w, const RTCRayHit& rh) const {
        w.result = hitToSample(rh);
        if (w.result.hit) {
            w.result.uv += w.uvOffset;
            w.result.t = w.t + refinedDistance(w, rh, w.ng);
            w.done = true;
            return;
        }
        if (!periodic) {
            w.done = true;
            w.result.hole = crossesSheet(w);
            return;
        }
        w.t += w.leave + 1e-9 * base->periodWorld;  // into the next tile (see tfar above)
        if (w.t > w.tExit + margin) {
            w.done = true;
            w.result.hole = crossesSheet(w);
        } else if (++w.guard >= 100000) {
            w.done = true;  // not a hole: the walk gave up inside the slab
        }
    }

    // The stretch's distance to its hit, and the hit triangle's normal (unnormalised), in
    // double: the ray met with the plane of the triangle Embree reports, its vertices as Embree
    // holds them. Embree's float distance is off by float rounding of the stretch (~1e-7 of
    // its length), which is more than a tiny relief is tall (docs/model.md §5b): a shadow ray
    // from such a point could start under the surface it leaves. Embree's own distance stays
    // where the two disagree by more than rounding (a ray along the triangle's plane).
    double refinedDistance(const Walk& w, const RTCRayHit& rh, Vec3d& ng) const {
        const double tf = double(rh.ray.tfar);
        ng = Vec3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
        uint32_t tri[3];
        hitTriangle(rh, tri);
        const Vec3d v0(vertices[tri[0]]), v1(vertices[tri[1]]), v2(vertices[tri[2]]);
        const Vec3d n = glm::cross(v1 - v0, v2 - v0);
        const double denom = glm::dot(w.dir, n);
        if (!(std::abs(denom) > 0)) return tf;
        const double t = glm::dot(v0 - w.segOrg, n) / denom;
        if (!(std::abs(t - tf) <= 1e-4 * (tf + margin))) return tf;
        ng = n;
        return t;
    }

    // Whether a ray that met nothing had to meet a plane's sheet: a plane's displaced sheet is
    // a height field over its rectangle (a periodic one over the whole plane), so a ray that
    // passes from above its highest vertex to below its lowest inside that rectangle crosses
    // it. A miss there is a hole between primitives.
    bool crossesSheet(const Walk& w) const {
        if (!base->isGrid() || w.dir.z == 0) return false;
        double tA = (boundsHi.z - w.o.z) / w.dir.z, tB = (boundsLo.z - w.o.z) / w.dir.z;
        if (tA > tB) std::swap(tA, tB);
        if (!w.line && tA < 0) return false;  // the eye is inside the slab
        if (periodic) return true;
        const double inset = 1e-7 * glm::length(boundsHi - boundsLo);
        for (double t : {tA, tB}) {
            const Vec3d p = w.o + w.dir * t;
            if (!(p.x > boundsLo.x + inset && p.x < boundsHi.x - inset &&
                  p.y > boundsLo.y + inset && p.y < boundsHi.y - inset))
                return false;
        }
        return true;
    }

    // What the last Embree call of a trace saw, for the double-precision check.
    struct Detail {
        RTCRayHit rh;
        Vec3d org{0}, dir{0};  // the ray as given to Embree, local frame, before rounding
        Vec2d uvOffset{0};     // tile offset added to the UV (periodic planes)
    };

    TruthSample trace(const Ray& ray, RTCIntersectContext* ctx, Detail* detail = nullptr,
                      Vec3d* ng = nullptr) const {
        Walk w;
        if (!start(ray, w)) return {};
        RTCRayHit rh;
        while (!w.done) {
            segment(w, rh);
            rtcIntersect1(scene, ctx, &rh);
            advance(w, rh);
        }
        if (detail)
            detail->rh = rh, detail->org = w.segOrg, detail->dir = w.dir,
            detail->uvOffset = w.uvOffset;
        if (ng) *ng = w.ng;
        return w.result;
    }

    // How far a shadow ray starts off the surface at `p` (local frame) along the unit normal
    // `n`: 1e-5 of the relief (a plane's l·|s|; a mesh's size, its relief bends with it), so
    // that scaling the heights and the light's slope together changes no shadow, and never
    // within float rounding of the point as Embree holds it (a periodic plane's within its
    // tile), projected on the normal.
    double shadowOffset(Vec3d p, Vec3d n) const {
        const double relief = base->isGrid() ? base->worldPerUv * std::abs(built.scale)
                                             : glm::length(boundsHi - boundsLo);
        if (periodic) {
            const double L = base->periodWorld;
            p.x = std::remainder(p.x, L), p.y = std::remainder(p.y, L);
        }
        const double rounding = 64.0 * double(std::numeric_limits<float>::epsilon()) *
                                (std::abs(p.x * n.x) + std::abs(p.y * n.y) + std::abs(p.z * n.z));
        return std::max(1e-5 * relief, rounding);
    }

    // The truth's shadow at the hit `s` of the ray `eye` (docs/model.md §5b): in shadow where
    // the sheet, on the side the eye sees, faces away from the light, or where a ray from the
    // hit toward the light meets the sheet (it starts shadowOffset off the surface).
    int8_t shadowAt(const Ray& eye, const TruthSample& s, Vec3d ng, Vec3d light,
                    RTCIntersectContext* ctx) const {
        if (!s.hit) return kShadowNone;
        // A plane's relief under a light at or below its horizon (light theta >= 90) is dark
        // everywhere, as the methods' marches say: a ray along the horizon would stay inside
        // the relief's slab, walking an infinite plane's tiles without end.
        if (base->isGrid() && !(glm::dot(light, base->grid->planeNormal) > 0)) return kShadowDark;
        if (glm::dot(ng, eye.dir) > 0) ng = -ng;
        const double len = glm::length(ng);
        if (!(len > 0)) return kShadowDark;  // a degenerate triangle: no side faces the light
        ng /= len;
        if (!(glm::dot(ng, light) > 0)) return kShadowDark;
        const Vec3d p = eye.origin + eye.dir * s.t;
        const double eps = shadowOffset(p - base->origin - shift, ng);
        return trace(Ray{p + ng * eps, light, false}, ctx).hit ? kShadowDark : kShadowLit;
    }

    // A pixel's truth, with its shadow where the view has a light.
    TruthSample tracePixel(const Camera& camera, const std::optional<Vec3d>& light, int x, int y,
                           RTCIntersectContext* ctx) const {
        const Ray ray = camera.pixelRay(x, y);
        Vec3d ng{0};
        TruthSample s = trace(ray, ctx, nullptr, &ng);
        if (light) s.shadow = shadowAt(ray, s, ng, *light, ctx);
        return s;
    }

    // A tile's rays as coherent streams: every live walk's stretch in one rtcIntersect1M
    // call, repeated while walks remain (periodic planes take a few rounds at grazing views).
    // Pixel (x, y) goes to out.at(x - ox, y - oy).
    void traceTile(const Camera& camera, const std::optional<Vec3d>& light, int x0, int x1, int y0,
                   int y1, Image2D<TruthSample>& out, int ox, int oy, std::vector<Walk>& walks,
                   std::vector<RTCRayHit>& rays, std::vector<int>& live) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        const int w = x1 - x0, n = w * (y1 - y0);
        walks.resize(size_t(n));  // start() resets what a walk reads
        live.clear();
        for (int k = 0; k < n; ++k)
            if (start(camera.pixelRay(x0 + k % w, y0 + k / w), walks[size_t(k)]))
                live.push_back(k);
            else
                walks[size_t(k)].done = true;
        rays.resize(size_t(n));
        while (!live.empty()) {
            for (size_t q = 0; q < live.size(); ++q) segment(walks[size_t(live[q])], rays[q]);
            rtcIntersect1M(scene, &ctx, rays.data(), unsigned(live.size()), sizeof(RTCRayHit));
            size_t keep = 0;
            for (size_t q = 0; q < live.size(); ++q) {
                Walk& wk = walks[size_t(live[q])];
                advance(wk, rays[q]);
                if (!wk.done) live[keep++] = live[q];
            }
            live.resize(keep);
        }
        RTCIntersectContext shadowCtx;  // shadow rays scatter: no coherence flag
        rtcInitIntersectContext(&shadowCtx);
        for (int k = 0; k < n; ++k) {
            Walk& wk = walks[size_t(k)];
            if (light && wk.result.hit)
                wk.result.shadow = shadowAt(camera.pixelRay(x0 + k % w, y0 + k / w), wk.result,
                                            wk.ng, *light, &shadowCtx);
            out.at(x0 + k % w - ox, y0 + k / w - oy) = wk.result;
        }
    }

    // Planes keep their vertices at (s, 0) and carry b as a translation N * l * b of the
    // rays, so a surface reached by any sequence of (s, b) updates is bit-identical to one
    // built at (s, b) directly (a resumed study reproduces an uninterrupted one).
    void displaceCanonical(const Displacement& disp) {
        if (!base->isGrid()) return displace(disp);
        displace(Displacement{disp.scale, 0.0});
        shift = base->grid->planeNormal * (base->worldPerUv * disp.bias);
    }

    // Writes P = S + N * l * (s*h + b) (docs/model.md §3, in double, rounded once to float) into
    // Embree's vertex buffer, and the bounds of the result.
    void displace(const Displacement& disp) {
        const BaseTessellation& b = *base;
        const size_t n = b.vertexCount();
        const double l = b.worldPerUv;
        struct Box {
            Vec3d lo{1e300}, hi{-1e300};
        };
        auto put = [&](size_t k, const Vec3d& p, const Vec3d& normal, double h, Box& acc) {
            Vec3f v(p + normal * (l * (disp.scale * h + disp.bias)));
            vertices[k] = v;
            acc.lo = glm::min(acc.lo, Vec3d(v));
            acc.hi = glm::max(acc.hi, Vec3d(v));
        };
        // A plane's lattice row by row: the same arithmetic as positionAt, uvAt and heightAt
        // per vertex, without their index division and branches (a fifth of a fine truth's
        // build went to them).
        const PlaneGrid* g = b.isGrid() ? &*b.grid : nullptr;
        const size_t rowLength = g ? size_t(g->nu) + 1 : 1;
        Box box = tbb::parallel_reduce(
            tbb::blocked_range<size_t>(0, n / rowLength, std::max<size_t>(1, 16384 / rowLength)),
            Box{},
            [&](const tbb::blocked_range<size_t>& r, Box acc) {
                throwIfCancelled();  // a huge sheet: Ctrl-C in Python stops here
                if (!g) {
                    for (size_t k = r.begin(); k < r.end(); ++k)
                        put(k, b.positionAt(k), b.normalAt(k), b.heightAt(k), acc);
                    return acc;
                }
                for (size_t j = r.begin(); j < r.end(); ++j) {
                    const double t = g->gridT(int(j));
                    for (int i = 0; i <= g->nu; ++i) {
                        const double s = g->gridS(i);
                        const Vec2d uv = PlaneGrid::blend(g->cornerUv, s, t);
                        put(j * rowLength + size_t(i), PlaneGrid::blend(g->cornerPosition, s, t),
                            g->planeNormal, sampleBilinear<double>(*g->heightMap, uv), acc);
                    }
                }
                return acc;
            },
            [](Box x, const Box& y) {
                x.lo = glm::min(x.lo, y.lo);
                x.hi = glm::max(x.hi, y.hi);
                return x;
            });
        boundsLo = box.lo;
        boundsHi = box.hi;
        // Rays start 1% of the sheet's diagonal outside its bounds (and at least 1e-6 world
        // units, for a flat sheet), so no hit lies behind a ray's origin.
        margin = 0.01 * glm::length(boundsHi - boundsLo) + 1e-6;
        built = disp;
        shift = Vec3d(0);
    }
};

}  // namespace pgt
