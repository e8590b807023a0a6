// The ground truth (MODEL.md §5): the displaced surface P = S + N*l*(s*h + b), tessellated
// with OpenSubdiv (Bfr) at `rate` samples per texel per axis and traced with Embree, one
// primary ray per pixel. The only module that includes Embree or OpenSubdiv headers.
#pragma once

#include <cstdint>
#include <memory>

#include "core/image.h"
#include "core/math.h"
#include "core/samples.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "raster/raster.h"
#include "heightfield/texture.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace pgt {

struct TruthBuildStats {
    int segmentsU = 0, segmentsV = 0;  // tessellation segments per axis
    int64_t vertices = 0, primitives = 0;  // primitives: grids or triangles
    int64_t geometryBytes = 0;             // Embree buffers (vertices + indices/grids)
    double tessellateMs = 0, buildMs = 0;
};

// The base surface tessellated with OpenSubdiv at `rate` samples per texel per axis, with the
// height sampled at every vertex: everything the truth needs that does not depend on the
// displacement (s, b), so a study builds it once per rate and reuses it.
struct BaseTessellation {
    int nu = 0, nv = 0;           // segments; vertices are (nu + 1) x (nv + 1), row-major in v
    Vec3d origin{0};              // positions are relative to this point (float precision)
    double worldPerUv = 1;        // l (MODEL.md §2)
    double periodWorld = 1;       // plane side L: the tile period of an infinite plane
    double periodUv = 1;          // tiling T: the UV period of the tile
    std::vector<Vec3f> position;  // S(u, v) - origin
    std::vector<Vec3f> normal;    // unit N(u, v)
    std::vector<Vec2d> uv;
    std::vector<double> height;   // h(u, v) from the shared bilinear sampler
    // Meshes: explicit triangles over the vertices (then nu, nv are 0 and no grid is used).
    std::vector<uint32_t> triangles;
    double tessellateMs = 0;
};

std::shared_ptr<const BaseTessellation> tessellatePlane(const Texture& height,
                                                        const PlaneBase& plane, int rate);

// The `polygonal` truth of a mesh (issue 4): the very triangles the rasteriser draws, each
// split uniformly into n^2 sub-triangles (n from the largest UV edge in texels x rate, one n
// for the whole mesh so shared edges get the same points), displaced along the interpolated
// vertex normal. Vertices on an edge shared by two drawn triangles are shared, so the sheet
// is watertight wherever the UVs are continuous (it opens at UV seams, as the real
// displaced asset does). `maxVertices` bounds the tessellation (n is lowered to fit).
// The `limit` truth of a mesh (issue 4): the OpenSubdiv limit surface of the control mesh
// (its scheme), tessellated face by face with the Bfr Tessellation API at a rate per cage
// edge from its UV length in texels x rate, displaced along the exact limit normal. Corners
// and edge points are shared between faces (evaluated once), split only where the UVs are
// discontinuous, so the sheet is watertight elsewhere. Throws std::invalid_argument on
// topology OpenSubdiv rejects.
std::shared_ptr<const BaseTessellation> tessellateLimitSurface(const Texture& height,
                                                               const ControlMesh& cage,
                                                               Scheme scheme, double worldPerUv,
                                                               int rate);

std::shared_ptr<const BaseTessellation> tessellateDrawnMesh(const Texture& height,
                                                            const BaseMesh& drawn,
                                                            double worldPerUv, int rate,
                                                            int64_t maxVertices = int64_t(1) << 26);

// How far Embree's single precision can be trusted (issue 5): sampled hits re-intersected
// in double with the same triangle, the UV difference in texels.
struct PrecisionCheck {
    int64_t samples = 0;
    int64_t edgeMisses = 0;  // float hits on an edge that the double ray misses by a hair
    double p50Texels = 0, p99Texels = 0, maxTexels = 0;
};

class TruthSurface {
public:
    // Displaces `base` by (s, b) (MODEL.md §3) and builds the Embree scene. `periodic`
    // repeats the tile forever in x and y (an infinite plane; needs an integer tiling).
    TruthSurface(std::shared_ptr<const BaseTessellation> base, const Displacement& disp,
                 TruthGeometry geometry, bool periodic);
    // Tessellates and builds in one step.
    TruthSurface(const Texture& height, const PlaneBase& plane, const Displacement& disp,
                 int rate, TruthGeometry geometry);
    ~TruthSurface();
    TruthSurface(const TruthSurface&) = delete;
    TruthSurface& operator=(const TruthSurface&) = delete;

    // First hit of one ray (world space) with the displaced sheet.
    TruthSample trace(const Ray& ray) const;
    // One primary ray per pixel centre, all cores.
    Image2D<TruthSample> traceFrame(const Camera& camera) const;

    const TruthBuildStats& stats() const;

    // Re-intersects up to `samples` seeded pixels' hits in double precision.
    PrecisionCheck checkPrecision(const Camera& camera, const Texture& height, int samples,
                                  uint32_t seed = 1) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The truth's own uncertainty (MODEL.md §5): the same frame at two rates.
struct TruthUncertainty {
    int rate = 0, rateFine = 0;
    int64_t pixelsCompared = 0;  // hit in both frames
    int64_t hitMismatch = 0;     // hit in one frame only (silhouette and border pixels)
    double p50Texels = 0, p99Texels = 0, maxTexels = 0;
};

TruthUncertainty compareTruthFrames(const Image2D<TruthSample>& coarse,
                                    const Image2D<TruthSample>& fine, const Texture& height,
                                    Address address);

}  // namespace pgt
