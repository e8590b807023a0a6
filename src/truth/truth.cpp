// Truth surface: a base tessellation (truth/tessellation.h) displaced along its normal into
// Embree grid or triangle geometry, refit or rebuilt per (s, b), traced in coherent tiles.
#include "truth/truth.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "compare/statistics.h"
#include "core/clock.h"
#include "core/error.h"

namespace pgt {

namespace {

// One Embree device for the process. Errors land in the callback, which records the first
// message; the build checks it (Embree tutorials: one error callback, not per-call checks).
std::mutex gEmbreeErrorMutex;
std::string gEmbreeError;

void embreeError(void*, RTCError code, const char* message) {
    std::lock_guard<std::mutex> lock(gEmbreeErrorMutex);
    if (gEmbreeError.empty())
        gEmbreeError =
            "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
}

RTCDevice device() {
    static RTCDevice d = [] {
        RTCDevice dev = rtcNewDevice(nullptr);
        if (!dev) throw std::runtime_error("cannot create an Embree device");
        rtcSetDeviceErrorFunction(dev, embreeError, nullptr);
        return dev;
    }();
    return d;
}

void throwIfEmbreeFailed() {
    std::lock_guard<std::mutex> lock(gEmbreeErrorMutex);
    if (!gEmbreeError.empty()) {
        std::string e = gEmbreeError;
        gEmbreeError.clear();
        throw std::runtime_error(e);
    }
}

// Embree warns without flush-to-zero and denormals-are-zero in every tracing thread.
void setTracingFpMode() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

// Grids are split into blocks of at most this many segments per side (Embree's limit is
// 32767 vertices); blocks share their boundary vertices, so the sheet stays watertight.
constexpr int kGridBlock = 1024;

}  // namespace

struct TruthSurface::Impl {
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

    // The candidate triangles (vertex indices) of a hit: one, or a grid cell's two.
    int candidates(const RTCRayHit& rh, uint32_t out[2][3]) const {
        if (!base->triangles.empty()) {
            const uint32_t* t = &base->triangles[size_t(rh.hit.primID) * 3];
            out[0][0] = t[0], out[0][1] = t[1], out[0][2] = t[2];
            return 1;
        }
        int ci, cj;
        if (geometry == TruthGeometry::Grid) {
            const RTCGrid& g = grids[rh.hit.primID];
            double gx = double(rh.hit.u) * (g.width - 1), gy = double(rh.hit.v) * (g.height - 1);
            ci = gridStart[rh.hit.primID].first + std::min(int(gx), g.width - 2);
            cj = gridStart[rh.hit.primID].second + std::min(int(gy), g.height - 2);
        } else {
            ci = int((rh.hit.primID / 2) % unsigned(nu));
            cj = int((rh.hit.primID / 2) / unsigned(nu));
        }
        uint32_t a = uint32_t(base->gridIndex(ci, cj)), b = a + 1;
        uint32_t c = uint32_t(base->gridIndex(ci, cj + 1)), d = c + 1;
        out[0][0] = a, out[0][1] = b, out[0][2] = c;
        out[1][0] = d, out[1][1] = c, out[1][2] = b;
        return 2;
    }

    // Vertex UVs interpolated over the triangle of cell (ci, cj) containing local (fx, fy):
    // the cell is split along its (1,0)-(0,1) diagonal.
    Vec2d cellUv(int ci, int cj, double fx, double fy) const {
        ci = std::clamp(ci, 0, nu - 1);
        cj = std::clamp(cj, 0, nv - 1);
        const BaseTessellation& t = *base;
        // A parallelogram's UVs are affine in (i, j): both triangles of a cell interpolate
        // the same affine function, which is the corners' blend at the hit's lattice point.
        if (t.affineUv)
            return BaseTessellation::blend(t.cornerUv, (ci + t.offsetI + fx) * t.invNu,
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
            // Grid hits report u, v over the whole grid primitive (BUILD-NOTES.md).
            const RTCGrid& g = grids[rh.hit.primID];
            const int i0 = gridStart[rh.hit.primID].first, j0 = gridStart[rh.hit.primID].second;
            double gx = double(rh.hit.u) * (g.width - 1), gy = double(rh.hit.v) * (g.height - 1);
            int ci = std::min(int(gx), g.width - 2), cj = std::min(int(gy), g.height - 2);
            s.uv = cellUv(i0 + ci, j0 + cj, gx - ci, gy - cj);
        } else if (!base->triangles.empty()) {
            const uint32_t* t = &base->triangles[size_t(rh.hit.primID) * 3];
            double u = rh.hit.u, v = rh.hit.v;
            s.uv = base->uv[t[0]] * (1 - u - v) + base->uv[t[1]] * u + base->uv[t[2]] * v;
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
        bool done = false;
        TruthSample result;
    };

    // Clips the ray; false when it misses the relief's bounds entirely.
    bool start(const Ray& ray, Walk& w) const {
        w.o = ray.origin - base->origin - shift;  // into the built sheet's frame, in double
        w.dir = ray.dir;
        w.guard = 0;
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
            w.done = true;
            return;
        }
        if (!periodic) {
            w.done = true;
            return;
        }
        w.t += w.leave + 1e-9 * base->periodWorld;
        if (++w.guard >= 100000 || w.t > w.tExit + margin) w.done = true;
    }

    // What the last Embree call of a trace saw, for the double-precision check.
    struct Detail {
        RTCRayHit rh;
        Vec3d org{0}, dir{0};  // the ray as given to Embree, local frame, before rounding
        Vec2d uvOffset{0};     // tile offset added to the UV (periodic planes)
    };

    TruthSample trace(const Ray& ray, RTCIntersectContext* ctx, Detail* detail = nullptr) const {
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
        return w.result;
    }

    // A tile's rays as coherent streams: every live walk's stretch in one rtcIntersect1M
    // call, repeated while walks remain (periodic planes take a few rounds at grazing views).
    void traceTile(const Camera& camera, int x0, int x1, int y0, int y1, Image2D<TruthSample>& out,
                   std::vector<Walk>& walks, std::vector<RTCRayHit>& rays,
                   std::vector<int>& live) const {
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
        for (int k = 0; k < n; ++k) out.at(x0 + k % w, y0 + k / w) = walks[size_t(k)].result;
    }

    // Planes keep their vertices at (s, 0) and carry b as a translation N * l * b of the
    // rays, so a surface reached by any sequence of (s, b) updates is bit-identical to one
    // built at (s, b) directly (a resumed study reproduces an uninterrupted one).
    void displaceCanonical(const Displacement& disp) {
        if (!base->isGrid()) return displace(disp);
        displace(Displacement{disp.scale, 0.0});
        shift = base->planeNormal * (base->worldPerUv * disp.bias);
    }

    // Writes P = S + N * l * (s*h + b) (MODEL.md §3, in double, rounded once to float) into
    // Embree's vertex buffer, and the bounds of the result.
    void displace(const Displacement& disp) {
        const BaseTessellation& b = *base;
        const size_t n = b.vertexCount();
        const double l = b.worldPerUv;
        struct Box {
            Vec3d lo{1e300}, hi{-1e300};
        };
        Box box = tbb::parallel_reduce(
            tbb::blocked_range<size_t>(0, n, 16384), Box{},
            [&](const tbb::blocked_range<size_t>& r, Box acc) {
                for (size_t k = r.begin(); k < r.end(); ++k) {
                    Vec3f v(b.positionAt(k) +
                            b.normalAt(k) * (l * (disp.scale * b.heightAt(k) + disp.bias)));
                    vertices[k] = v;
                    acc.lo = glm::min(acc.lo, Vec3d(v));
                    acc.hi = glm::max(acc.hi, Vec3d(v));
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
        margin = 0.01 * glm::length(boundsHi - boundsLo) + 1e-6;
        built = disp;
        shift = Vec3d(0);
    }
};

TruthSurface::TruthSurface(const Texture& height, const PlaneBase& plane, const Displacement& disp,
                           int rate, TruthGeometry geometry)
    : TruthSurface(tessellatePlane(height, plane, rate), disp, geometry, false) {}

TruthSurface::TruthSurface(std::shared_ptr<const BaseTessellation> base, const Displacement& disp,
                           TruthGeometry geometry, bool periodic)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.base = std::move(base);
    m.geometry = geometry;
    m.periodic = periodic;
    m.nu = m.base->nu;
    m.nv = m.base->nv;
    const bool meshTriangles = !m.base->isGrid();
    PGT_CHECK(!(meshTriangles && (periodic || geometry == TruthGeometry::Grid)));
    if (periodic) {
        double T = m.base->periodUv;
        PGT_CHECK_LT(std::fabs(T - std::round(T)), 1e-9);  // scene validation guarantees it
    }
    m.stats.tessellateMs = m.base->tessellateMs;
    m.stats.segmentsU = m.nu;
    m.stats.segmentsV = m.nv;
    const size_t nVerts = m.base->vertexCount();
    m.stats.vertices = int64_t(nVerts);

    auto t1 = Clock::now();
    RTCDevice dev = device();
    m.scene = rtcNewScene(dev);
    // Triangles are built refittable: Embree refits only a dynamic scene's per-geometry BVH
    // (two-level, scene quality LOW) whose geometry was built with quality REFIT. Measured on
    // a 2.1M-triangle sheet: refit 39-42 ms vs rebuild 311-333 ms, same trace speed
    // (BM_TruthUpdate, BM_TruthFrame). Grids gain nothing from a refit: one-level build.
    const bool refittable = geometry == TruthGeometry::Triangles;
    if (refittable) {
        rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_DYNAMIC);
        rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_LOW);
    }
    m.geom = rtcNewGeometry(
        dev, geometry == TruthGeometry::Grid ? RTC_GEOMETRY_TYPE_GRID : RTC_GEOMETRY_TYPE_TRIANGLE);
    // rtcSetNewGeometryBuffer pads the buffer as Embree requires for its SIMD loads.
    m.vertices = static_cast<Vec3f*>(rtcSetNewGeometryBuffer(
        m.geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(Vec3f), nVerts));
    throwIfEmbreeFailed();
    PGT_CHECK(m.vertices != nullptr);
    m.displaceCanonical(disp);
    m.stats.geometryBytes = int64_t(nVerts * sizeof(Vec3f));
    if (geometry == TruthGeometry::Grid) {
        for (int j0 = 0; j0 < m.nv; j0 += kGridBlock)
            for (int i0 = 0; i0 < m.nu; i0 += kGridBlock) {
                RTCGrid g;
                g.startVertexID = unsigned(m.base->gridIndex(i0, j0));
                g.stride = unsigned(m.nu + 1);
                g.width = static_cast<unsigned short>(std::min(kGridBlock, m.nu - i0) + 1);
                g.height = static_cast<unsigned short>(std::min(kGridBlock, m.nv - j0) + 1);
                m.grids.push_back(g);
                m.gridStart.push_back({i0, j0});
            }
        auto* gb = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(
            m.geom, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid), m.grids.size()));
        std::copy(m.grids.begin(), m.grids.end(), gb);
        m.stats.primitives = int64_t(m.grids.size());
        m.stats.geometryBytes += int64_t(m.grids.size() * sizeof(RTCGrid));
    } else if (meshTriangles) {
        const auto& tri = m.base->triangles;
        auto* ib = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(m.geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(unsigned), tri.size() / 3));
        std::copy(tri.begin(), tri.end(), ib);
        m.stats.primitives = int64_t(tri.size() / 3);
        m.stats.geometryBytes += int64_t(tri.size() * sizeof(unsigned));
    } else {
        size_t nTri = size_t(m.nu) * m.nv * 2;
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            m.geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nTri));
        tbb::parallel_for(0, m.nv, [&](int cj) {
            for (int ci = 0; ci < m.nu; ++ci) {
                unsigned a = unsigned(m.base->gridIndex(ci, cj)), b = a + 1;
                unsigned c = unsigned(m.base->gridIndex(ci, cj + 1)), d = c + 1;
                size_t k = (size_t(cj) * m.nu + ci) * 6;
                ib[k + 0] = a, ib[k + 1] = b, ib[k + 2] = c;  // barycentrics: u on b, v on c
                ib[k + 3] = d, ib[k + 4] = c, ib[k + 5] = b;  // u on c, v on b
            }
        });
        m.stats.primitives = int64_t(nTri);
        m.stats.geometryBytes += int64_t(nTri * 3 * sizeof(unsigned));
    }
    rtcSetGeometryBuildQuality(m.geom,
                               refittable ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_MEDIUM);
    rtcCommitGeometry(m.geom);  // geometries must be committed before they are attached
    rtcAttachGeometry(m.scene, m.geom);
    rtcCommitScene(m.scene);
    m.stats.buildMs = msSince(t1);
    throwIfEmbreeFailed();
}

TruthSurface::~TruthSurface() {
    if (impl_ && impl_->geom) rtcReleaseGeometry(impl_->geom);
    if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
}

const TruthBuildStats& TruthSurface::stats() const { return impl_->stats; }
TruthUpdate TruthSurface::lastUpdate() const { return impl_->lastUpdate; }

void TruthSurface::setDisplacement(const Displacement& disp, TruthUpdate update) {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    // Measured (README "Performance", BM_TruthUpdate): a triangle BVH refits in an eighth of
    // its rebuild; a grid's refit is no faster than its rebuild, and a rebuilt BVH stays tight.
    const bool translatable = m.base->isGrid() && disp.scale == m.built.scale;
    if (update == TruthUpdate::Auto)
        update = translatable                        ? TruthUpdate::Translate
                 : m.geometry == TruthGeometry::Grid ? TruthUpdate::Rebuild
                                                     : TruthUpdate::Refit;
    if (update == TruthUpdate::Translate) {
        PGT_CHECK(translatable);
        m.shift = m.base->planeNormal * (m.base->worldPerUv * (disp.bias - m.built.bias));
        m.lastUpdate = update;
        m.stats.updateMs = msSince(t0);
        return;
    }
    m.displaceCanonical(disp);
    rtcUpdateGeometryBuffer(m.geom, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcSetGeometryBuildQuality(
        m.geom, update == TruthUpdate::Refit ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_MEDIUM);
    rtcCommitGeometry(m.geom);
    rtcCommitScene(m.scene);
    m.lastUpdate = update;
    m.stats.updateMs = msSince(t0);
    throwIfEmbreeFailed();
}

TruthSample TruthSurface::trace(const Ray& ray) const {
    setTracingFpMode();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    return impl_->trace(ray, &ctx);
}

namespace {
// Frames are traced in 8 x 8 pixel tiles: one coherent stream per tile, tiles over threads.
constexpr int kTile = 8;
struct TileGrid {
    int X0, Y0, X1, Y1, across, count;
    TileGrid(int w, int h) : TileGrid(PixelRect{0, 0, w, h}) {}
    explicit TileGrid(PixelRect r)
        : X0(r.x0),
          Y0(r.y0),
          X1(r.x1),
          Y1(r.y1),
          across((r.x1 - r.x0 + kTile - 1) / kTile),
          count(across * ((r.y1 - r.y0 + kTile - 1) / kTile)) {}
    int x0(int t) const { return X0 + (t % across) * kTile; }
    int y0(int t) const { return Y0 + (t / across) * kTile; }
    int x1(int t) const { return std::min(x0(t) + kTile, X1); }
    int y1(int t) const { return std::min(y0(t) + kTile, Y1); }
};
}  // namespace

Image2D<TruthSample> TruthSurface::traceFrame(const Camera& camera, TraceMode mode) const {
    Image2D<TruthSample> out;
    traceFrame(camera, out, mode);
    return out;
}

void TruthSurface::traceFrame(const Camera& camera, Image2D<TruthSample>& out,
                              TraceMode mode) const {
    if (out.width != camera.width() || out.height != camera.height())
        out = Image2D<TruthSample>(camera.width(), camera.height());
    traceBlock(camera, out, PixelRect{0, 0, camera.width(), camera.height()}, mode);
}

void TruthSurface::traceBlock(const Camera& camera, Image2D<TruthSample>& out, PixelRect block,
                              TraceMode mode) const {
    PGT_CHECK(out.width == camera.width() && out.height == camera.height());
    PGT_CHECK(block.x0 >= 0 && block.y0 >= 0 && block.x1 <= out.width && block.y1 <= out.height);
    const Impl& m = *impl_;
    const TileGrid tiles(block);
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles.count, 4), [&](const auto& r) {
        setTracingFpMode();
        if (mode == TraceMode::Coherent) {
            // Scratch per thread, reused across tiles: no allocation per pixel.
            thread_local std::vector<Impl::Walk> walks;
            thread_local std::vector<RTCRayHit> rays;
            thread_local std::vector<int> live;
            for (int t = r.begin(); t < r.end(); ++t)
                m.traceTile(camera, tiles.x0(t), tiles.x1(t), tiles.y0(t), tiles.y1(t), out, walks,
                            rays, live);
            return;
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int t = r.begin(); t < r.end(); ++t)
            for (int y = tiles.y0(t); y < tiles.y1(t); ++y)
                for (int x = tiles.x0(t); x < tiles.x1(t); ++x)
                    out.at(x, y) = m.trace(camera.pixelRay(x, y), &ctx);
    });
}

BareLoopTiming TruthSurface::timeBareEmbreeLoop(const Camera& camera, TraceMode mode,
                                                int repeats) const {
    const Impl& m = *impl_;
    PGT_CHECK(!m.periodic);  // one Embree ray per pixel
    const TileGrid tiles(camera.width(), camera.height());
    // The rays exactly as traceFrame hands them to Embree, tile by tile, made before the
    // clock starts; rays that miss the bounds are made inactive (tfar < tnear).
    std::vector<RTCRayHit> made;
    std::vector<size_t> first(size_t(tiles.count) + 1, 0);
    for (int t = 0; t < tiles.count; ++t) {
        for (int y = tiles.y0(t); y < tiles.y1(t); ++y)
            for (int x = tiles.x0(t); x < tiles.x1(t); ++x) {
                Impl::Walk w;
                RTCRayHit rh;
                bool inside = m.start(camera.pixelRay(x, y), w);
                m.segment(w, rh);
                if (!inside) rh.ray.tfar = -1.0f;
                made.push_back(rh);
            }
        first[size_t(t) + 1] = made.size();
    }
    std::vector<RTCRayHit> rays;
    std::vector<double> ms;
    for (int rep = 0; rep < std::max(1, repeats); ++rep) {
        rays = made;
        auto t0 = Clock::now();
        tbb::parallel_for(tbb::blocked_range<int>(0, tiles.count, 4), [&](const auto& r) {
            setTracingFpMode();
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            if (mode == TraceMode::Coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            for (int t = r.begin(); t < r.end(); ++t) {
                size_t a = first[size_t(t)], b = first[size_t(t) + 1];
                if (mode == TraceMode::Coherent)
                    rtcIntersect1M(m.scene, &ctx, &rays[a], unsigned(b - a), sizeof(RTCRayHit));
                else
                    for (size_t k = a; k < b; ++k) rtcIntersect1(m.scene, &ctx, &rays[k]);
            }
        });
        ms.push_back(msSince(t0));
    }
    std::sort(ms.begin(), ms.end());
    return {ms[ms.size() / 2], int64_t(made.size())};
}

namespace {
// Moller-Trumbore in double: t and the barycentrics (b1 on p1, b2 on p2) where the ray meets
// the triangle's plane; inside when b1, b2 >= 0 and b1 + b2 <= 1 (within `slack`).
bool intersectDouble(Vec3d o, Vec3d d, Vec3d p0, Vec3d p1, Vec3d p2, double slack, double& t,
                     double& b1, double& b2) {
    Vec3d e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
    double det = glm::dot(e1, pv);
    if (det == 0 || !std::isfinite(det)) return false;
    Vec3d tv = o - p0, qv = glm::cross(tv, e1);
    b1 = glm::dot(tv, pv) / det;
    b2 = glm::dot(d, qv) / det;
    t = glm::dot(e2, qv) / det;
    return b1 >= -slack && b2 >= -slack && b1 + b2 <= 1 + slack;
}
}  // namespace

PrecisionCheck TruthSurface::checkPrecision(const Camera& camera, const Texture& height,
                                            int samples, uint32_t seed) const {
    const Impl& m = *impl_;
    PrecisionCheck pc;
    std::vector<std::pair<int, int>> pixels;
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) pixels.push_back({x, y});
    std::mt19937 rng(seed);
    std::shuffle(pixels.begin(), pixels.end(), rng);
    setTracingFpMode();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::vector<double> errs;
    for (const auto& [x, y] : pixels) {
        if (int64_t(errs.size()) >= samples) break;
        Impl::Detail det;
        TruthSample s = m.trace(camera.pixelRay(x, y), &ctx, &det);
        if (!s.hit) continue;
        uint32_t tri[2][3];
        int n = m.candidates(det.rh, tri);
        // Re-intersect the hit triangle in double (the same float vertices, the unrounded
        // ray); a grid cell's two triangles are both tried, the nearer inside one wins.
        double bestT = INFINITY;
        Vec2d uv(0);
        for (int k = 0; k < n; ++k) {
            Vec3d p[3];
            for (int c = 0; c < 3; ++c) p[c] = Vec3d(m.vertices[tri[k][c]]);
            double t, b1, b2;
            if (!intersectDouble(det.org, det.dir, p[0], p[1], p[2], 1e-6, t, b1, b2)) continue;
            if (t < bestT) {
                bestT = t;
                uv = m.base->uvAt(tri[k][0]) * (1 - b1 - b2) + m.base->uvAt(tri[k][1]) * b1 +
                     m.base->uvAt(tri[k][2]) * b2 + det.uvOffset;
            }
        }
        if (!std::isfinite(bestT)) {
            ++pc.edgeMisses;  // the float hit lies on an edge the double ray just misses
            continue;
        }
        errs.push_back(uvErrorTexels(s.uv, uv, height.width, height.height, height.address));
    }
    pc.samples = int64_t(errs.size());
    if (!errs.empty()) {
        pc.p50Texels = percentile(errs, 0.5);
        pc.p99Texels = percentile(errs, 0.99);
        pc.maxTexels = *std::max_element(errs.begin(), errs.end());
    }
    return pc;
}

}  // namespace pgt
