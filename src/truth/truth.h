// The ground truth (docs/model.md §5): the displaced surface P = S + N*l*(s*h + b), tessellated
// with OpenSubdiv (Bfr) at `rate` samples per texel per axis and traced with Embree, one
// primary ray per pixel. The only module that includes Embree or OpenSubdiv headers.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "core/image.h"
#include "core/math.h"
#include "core/samples.h"
#include "heightfield/texture.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "raster/raster.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "truth/tessellation.h"

namespace pgt {

struct TruthBuildStats {
    int segmentsU = 0, segmentsV = 0;      // tessellation segments per axis
    int64_t vertices = 0, primitives = 0;  // primitives: grids or triangles
    int64_t geometryBytes = 0;             // Embree buffers (vertices + indices/grids)
    double tessellateMs = 0, buildMs = 0;
    double updateMs = 0;  // the last setDisplacement: displace + refit/rebuild
};

// How far Embree's single precision can be trusted: sampled hits re-intersected
// in double with the same triangle, the UV difference in texels.
struct PrecisionCheck {
    int64_t samples = 0;
    int64_t edgeMisses = 0;  // float hits on an edge that the double ray misses by a hair
    double p50Texels = 0, p99Texels = 0, maxTexels = 0;
};

// How a (s, b) change reaches Embree: new vertices then a full BVH rebuild, or a refit of
// the existing BVH (RTC_BUILD_QUALITY_REFIT: same topology, boxes recomputed). Translate:
// on a plane (one normal N) a bias change alone moves the sheet by N * l * (b' - b), so the
// rays move instead and Embree does nothing (Auto picks it whenever it applies).
enum class TruthUpdate { Auto, Rebuild, Refit, Translate };

// How a frame's rays are handed to Embree: one rtcIntersect1 per ray, or a tile's rays as a
// coherent stream (rtcIntersect1M with RTC_INTERSECT_CONTEXT_FLAG_COHERENT).
enum class TraceMode { Single, Coherent };

// The same frame's rays traced by nothing but Embree calls: the rays are made
// before the clock starts, the loop over tiles only calls Embree. Median of the repeats.
struct BareLoopTiming {
    double bareMs = 0;  // the bare loop
    int64_t rays = 0;
};

class TruthSurface {
  public:
    // Displaces `base` by (s, b) (docs/model.md §3) and builds the Embree scene. `periodic`
    // repeats the tile forever in x and y (an infinite plane; needs an integer tiling).
    TruthSurface(std::shared_ptr<const BaseTessellation> base, const Displacement& disp,
                 TruthGeometry geometry, bool periodic);
    // Tessellates and builds in one step.
    TruthSurface(const Texture& height, const PlaneBase& plane, const Displacement& disp, int rate,
                 TruthGeometry geometry);
    ~TruthSurface();
    TruthSurface(const TruthSurface&) = delete;
    TruthSurface& operator=(const TruthSurface&) = delete;

    // Re-displaces the same tessellation by a new (s, b): the vertices are rewritten in
    // Embree's buffer and the BVH rebuilt or refitted (Auto: a translation when only b of a
    // plane changed, else the one measured faster for the geometry, docs/performance.md).
    // Nothing is reallocated.
    void setDisplacement(const Displacement& disp, TruthUpdate update = TruthUpdate::Auto);

    // First hit of one ray (world space) with the displaced sheet.
    TruthSample trace(const Ray& ray) const;
    // One primary ray per pixel (camera.pixelRay), tiles over all cores. With a `light` (the
    // unit world direction toward it, scene.h lightToward), every hit's shadow ray too.
    Image2D<TruthSample> traceFrame(const Camera& camera, TraceMode mode = TraceMode::Coherent,
                                    const std::optional<Vec3d>& light = std::nullopt) const;
    // The same into `out`, reusing its memory when it already has the camera's size.
    void traceFrame(const Camera& camera, Image2D<TruthSample>& out,
                    TraceMode mode = TraceMode::Coherent,
                    const std::optional<Vec3d>& light = std::nullopt) const;
    // Only the pixels of `block` (out must have the camera's size already).
    void traceBlock(const Camera& camera, Image2D<TruthSample>& out, PixelRect block,
                    TraceMode mode = TraceMode::Coherent,
                    const std::optional<Vec3d>& light = std::nullopt) const;
    // Only the pixels of `rect`, into `out` resized to the rectangle (pixel (x, y) at
    // out.at(x - rect.x0, y - rect.y0)): a band of a frame traced on its own.
    void traceRect(const Camera& camera, PixelRect rect, Image2D<TruthSample>& out,
                   TraceMode mode = TraceMode::Coherent,
                   const std::optional<Vec3d>& light = std::nullopt) const;
    // The bare-Embree baseline for traceFrame on the same rays (benchmarks; planes that are
    // not periodic, where a pixel's ray is one Embree ray).
    BareLoopTiming timeBareEmbreeLoop(const Camera& camera, TraceMode mode, int repeats) const;

    const TruthBuildStats& stats() const;
    TruthUpdate lastUpdate() const;  // what the last setDisplacement did

    // Re-intersects up to `samples` seeded pixels' hits in double precision.
    PrecisionCheck checkPrecision(const Camera& camera, const Texture& height, int samples,
                                  uint32_t seed = 1) const;

  private:
    void traceInto(const Camera& camera, PixelRect block, Image2D<TruthSample>& out, int ox, int oy,
                   TraceMode mode, const std::optional<Vec3d>& light) const;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pgt
