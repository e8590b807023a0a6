// Truth surface: a base tessellation (truth/tessellation.h) displaced along its normal into
// Embree grid or triangle geometry, refit or rebuilt per (s, b), traced in coherent tiles.
#include "truth/truth.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "compare/statistics.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/percentile.h"
#include "truth/embree_device.h"
#include "truth/embree_sheet.h"

namespace pgt {

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
    const bool meshTriangles = !m.base->isGrid();
    if (!meshTriangles) {  // a mesh has no lattice (its grid is empty)
        m.nu = m.base->grid->nu;
        m.nv = m.base->grid->nv;
    }
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
    RTCDevice dev = embreeDevice();
    m.scene = rtcNewScene(dev);
    // Triangles are built refittable: Embree refits only a dynamic scene's per-geometry BVH
    // (two-level, scene quality LOW) whose geometry was built with quality REFIT. Measured on
    // a 2.1M-triangle sheet: refit 39-42 ms vs rebuild 311-333 ms, same trace speed
    // (BM_TruthUpdate, BM_TruthFrame). Grids gain nothing from a refit: one-level build.
    const bool refittable = geometry == TruthGeometry::Triangles;
    // Robust: without it a ray through a shared edge or a grid line can pass between the two
    // primitives (Embree's fast box and triangle tests are not watertight there), which puts
    // whole rows of holes into centred, power-of-two views of a sheet at a round height
    // (docs/model.md §5). Its cost is in docs/performance.md. A grid's scene is compact: 37 MB
    // less of a 512^2 frame's 239, the same hits, its build no slower and coherent rays as fast
    // (single rays 6 % slower; docs/performance.md).
    rtcSetSceneFlags(m.scene, refittable ? RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST
                                         : RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_COMPACT);
    // A build of a huge sheet takes minutes: Embree asks this as it goes, and a cancel (Ctrl-C
    // in Python) stops it there (rtcCommitScene returns; throwIfCancelled below).
    rtcSetSceneProgressMonitorFunction(
        m.scene, [](void*, double) { return !cancelRequested(); }, nullptr);
    if (refittable) rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_LOW);
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
                g.startVertexID = unsigned(m.base->grid->gridIndex(i0, j0));
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
        const auto& tri = m.base->sheet.triangles;
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
                unsigned a = unsigned(m.base->grid->gridIndex(ci, cj)), b = a + 1;
                unsigned c = unsigned(m.base->grid->gridIndex(ci, cj + 1)), d = c + 1;
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
    throwIfCancelled();
    throwIfEmbreeFailed();
}

TruthSurface::~TruthSurface() = default;  // Impl releases the Embree objects

const TruthBuildStats& TruthSurface::stats() const { return impl_->stats; }
TruthUpdate TruthSurface::lastUpdate() const { return impl_->lastUpdate; }

void TruthSurface::setDisplacement(const Displacement& disp, TruthUpdate update) {
    Impl& m = *impl_;
    auto t0 = Clock::now();
    // Measured (docs/performance.md, BM_TruthUpdate): a triangle BVH refits in an eighth of
    // its rebuild; a grid's refit is no faster than its rebuild, and a rebuilt BVH stays tight.
    const bool translatable = m.base->isGrid() && disp.scale == m.built.scale;
    if (update == TruthUpdate::Auto)
        update = translatable                        ? TruthUpdate::Translate
                 : m.geometry == TruthGeometry::Grid ? TruthUpdate::Rebuild
                                                     : TruthUpdate::Refit;
    if (update == TruthUpdate::Translate) {
        PGT_CHECK(translatable);
        m.shift = m.base->grid->planeNormal * (m.base->worldPerUv * (disp.bias - m.built.bias));
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
    throwIfCancelled();
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

Image2D<TruthSample> TruthSurface::traceFrame(const Camera& camera, TraceMode mode,
                                              const std::optional<Vec3d>& light) const {
    Image2D<TruthSample> out;
    traceFrame(camera, out, mode, light);
    return out;
}

void TruthSurface::traceFrame(const Camera& camera, Image2D<TruthSample>& out, TraceMode mode,
                              const std::optional<Vec3d>& light) const {
    if (out.width != camera.width() || out.height != camera.height())
        out = Image2D<TruthSample>(camera.width(), camera.height());
    traceBlock(camera, out, PixelRect{0, 0, camera.width(), camera.height()}, mode, light);
}

void TruthSurface::traceBlock(const Camera& camera, Image2D<TruthSample>& out, PixelRect block,
                              TraceMode mode, const std::optional<Vec3d>& light) const {
    PGT_CHECK(out.width == camera.width() && out.height == camera.height());
    traceInto(camera, block, out, 0, 0, mode, light);
}

void TruthSurface::traceRect(const Camera& camera, PixelRect rect, Image2D<TruthSample>& out,
                             TraceMode mode, const std::optional<Vec3d>& light) const {
    if (out.width != rect.width() || out.height != rect.height())
        out = Image2D<TruthSample>(rect.width(), rect.height());
    traceInto(camera, rect, out, rect.x0, rect.y0, mode, light);
}

void TruthSurface::traceInto(const Camera& camera, PixelRect block, Image2D<TruthSample>& out,
                             int ox, int oy, TraceMode mode,
                             const std::optional<Vec3d>& light) const {
    PGT_CHECK(block.x0 >= 0 && block.y0 >= 0 && block.x1 <= camera.width() &&
              block.y1 <= camera.height());
    PGT_CHECK(block.x0 >= ox && block.y0 >= oy && block.x1 - ox <= out.width &&
              block.y1 - oy <= out.height);
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
                m.traceTile(camera, light, tiles.x0(t), tiles.x1(t), tiles.y0(t), tiles.y1(t), out,
                            ox, oy, walks, rays, live);
            return;
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (int t = r.begin(); t < r.end(); ++t)
            for (int y = tiles.y0(t); y < tiles.y1(t); ++y)
                for (int x = tiles.x0(t); x < tiles.x1(t); ++x)
                    out.at(x - ox, y - oy) = m.tracePixel(camera, light, x, y, &ctx);
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
    return {percentile(ms, 0.5), int64_t(made.size())};
}

}  // namespace pgt
