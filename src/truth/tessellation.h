// The truth's base tessellations (docs/model.md §5): a plane's implicit lattice, a mesh's drawn
// triangles split at the truth's rate, or its OpenSubdiv limit surface (Bfr), with the
// window of a plane a view can see. Independent of the displacement (s, b).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "heightfield/texture.h"
#include "mesh/base_mesh.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace pgt {

// A plane's regular (nu + 1) x (nv + 1) vertex lattice, stored implicitly: OpenSubdiv (Bfr)
// evaluates the quad's corners, and vertex (i, j) is their bilinear blend at (i / nu, j / nv)
// -- exactly what Bfr's bilinear scheme evaluates there (tested) -- with the height sampled
// from the map when the surface is displaced. Nothing is stored per vertex, so the only
// per-vertex memory of a plane's truth is Embree's 12-byte vertex (a 4096^2 map at rate 4
// would otherwise need 13 GB). Its size is PlaneLattice's (scene/scene.h).
struct PlaneGrid {
    int nu = 0, nv = 0;  // segments
    // A window of the plane's vertex lattice (TruthWindow): local vertex (i, j) is lattice
    // vertex (i + offsetI, j + offsetJ) of the whole tile's fullNu x fullNv segments
    // (outside [0, fullNu] on an infinite plane: the tile's continuation).
    int offsetI = 0, offsetJ = 0, fullNu = 0, fullNv = 0;
    double invNu = 1, invNv = 1;
    // The Bfr-evaluated corners at (s, t) = (0,0), (1,0), (0,1), (1,1), the unit normal and
    // the height map the vertices sample.
    Vec3d cornerPosition[4]{};
    Vec2d cornerUv[4]{};
    Vec3d planeNormal{0, 0, 1};
    std::shared_ptr<const Texture> heightMap;
    bool affineUv = false;  // the corners' UVs form a parallelogram (every plane does)

    size_t vertexCount() const { return size_t(nu + 1) * size_t(nv + 1); }
    size_t gridIndex(int i, int j) const { return size_t(j) * size_t(nu + 1) + size_t(i); }
    // Vertex (i, j) of the grid: the corners blended at (i / nu, j / nv).
    template <class T>
    static T blend(const T c[4], double s, double t) {
        return (c[0] * (1 - s) + c[1] * s) * (1 - t) + (c[2] * (1 - s) + c[3] * s) * t;
    }
    Vec2d gridUv(int i, int j) const { return blend(cornerUv, gridS(i), gridT(j)); }
    // Lattice i / fullNu and j / fullNv without a division per call, exact at the tile edge.
    double gridS(int i) const {
        i += offsetI;
        return i == fullNu ? 1.0 : i * invNu;
    }
    double gridT(int j) const {
        j += offsetJ;
        return j == fullNv ? 1.0 : j * invNv;
    }
};

// A mesh's explicit vertices (relative to BaseTessellation::origin) and triangles.
struct TriangleSheet {
    std::vector<Vec3f> position;  // S(u, v) - origin
    std::vector<Vec3f> normal;    // unit N(u, v)
    std::vector<Vec2d> uv;
    std::vector<double> height;  // h(u, v) from the shared bilinear sampler
    std::vector<uint32_t> triangles;
};

// The base surface tessellated with OpenSubdiv at `rate` samples per texel per axis:
// everything the truth needs that does not depend on the displacement (s, b), so a study
// builds it once per rate and reuses it. A plane is a PlaneGrid, a mesh a TriangleSheet.
struct BaseTessellation {
    std::optional<PlaneGrid> grid;  // planes
    TriangleSheet sheet;            // meshes (empty for planes)
    Vec3d origin{0};                // positions are relative to this point (float precision)
    double worldPerUv = 1;          // l (docs/model.md §2)
    double periodWorld = 1;         // plane side L: the tile period of an infinite plane
    double periodUv = 1;            // tiling T: the UV period of the tile
    double tessellateMs = 0;

    bool isGrid() const { return grid.has_value(); }
    size_t vertexCount() const { return isGrid() ? grid->vertexCount() : sheet.position.size(); }
    Vec3d positionAt(size_t k) const;
    Vec3d normalAt(size_t k) const;
    Vec2d uvAt(size_t k) const;
    double heightAt(size_t k) const;  // h at the vertex (sampleBilinear<double>)
    // Bytes held per vertex by this object (0 for planes).
    size_t bytes() const;
};

// The part of a plane's UV domain a frame can see: the texels under the camera's frustum
// between the lowest and the highest displaced height (the displacement is along the
// plane's normal, so a hit's UV lies under its ray's passage through that slab), plus a
// margin, and, when the camera carries a light above the plane's horizon, everything its
// shadow rays can meet: the region moved toward the light by the slab's height over the light's
// slope, (z_hi - z_lo) / L.z * L.xy. Unwrapped UV (may leave [0, tiling] on an infinite plane).
// `reach` scales the margin and the light's reach: the truth's finer pass is built over a
// window twice as wide, so that a window too small for a shadow shows as a disagreement
// between the two passes (docs/model.md §5).
struct TruthWindow {
    bool limited = false;  // false: the whole plane (tile)
    bool empty = false;    // limited to nothing: the view misses the plane
    Vec2d uvMin{0}, uvMax{0};
};
// The height map's texel range [lo, hi]: what the relief's slab spans. One pass over every
// texel on every core, polling the cancel flag (a 16384^2 map is a gigabyte).
struct TexelRange {
    float lo = 0, hi = 0;
};
TexelRange texelRange(const Texture& height);
// A block of a frame's pixels [x0, x1) x [y0, y1); empty = the whole frame. With a `light`
// (scene.h lightToward), the window reaches as far toward it as a shadow ray can. `range`: the
// map's texelRange when the caller has it (a frame cut into blocks asks for many windows of
// one map); null computes it.
TruthWindow viewWindow(const PlaneBase& plane, const Texture& height, const Displacement& disp,
                       const Camera& camera, const std::optional<Vec3d>& light,
                       PixelRect block = {}, double reach = 1, const TexelRange* range = nullptr);
// The window a frame's truth is built over: viewWindow, or the whole plane (not limited) when
// the window is not clearly smaller than the tile (at least half its area: a grazing view of
// an infinite plane, whose tile is then walked periodically) or the view misses the plane.
// The one rule for what is built and what the memory estimate counts. (A block's window is
// kept: blocks need their windows.)
TruthWindow frameWindow(const PlaneBase& plane, const Texture& height, const Displacement& disp,
                        const Camera& camera, const std::optional<Vec3d>& light,
                        PixelRect block = {}, double reach = 1, const TexelRange* range = nullptr);
// The truth's memory per vertex, the one place these figures live: a plane's grid, Embree's
// BVH included (measured: 3.27 GB peak for 84M grid vertices, a 4096^2 map at rates 1 and 2),
// and a mesh's explicit sheet (its per-vertex data, Embree's build, the frame's rays; measured
// on a 3 x 3-tiled quad: 5.9 million vertices at rates 2 and 4 took 1.84 GB).
constexpr double kTruthBytesPerGridVertex = 40;
constexpr double kTruthBytesPerSheetVertex = 300;

std::shared_ptr<const BaseTessellation> tessellatePlane(const Texture& height,
                                                        const PlaneBase& plane, int rate,
                                                        const TruthWindow& window = {});
// The same over a height map it shares (no copy: a 16384^2 map is a gigabyte).
std::shared_ptr<const BaseTessellation> tessellatePlane(std::shared_ptr<const Texture> height,
                                                        const PlaneBase& plane, int rate,
                                                        const TruthWindow& window = {});

// The `limit` truth of a mesh: the OpenSubdiv limit surface of the control mesh
// (its scheme), tessellated face by face with the Bfr Tessellation API at a rate per cage
// edge from its UV length in texels x rate, displaced along the exact limit normal. Corners
// and edge points are shared between faces (evaluated once), split only where the UVs are
// discontinuous, so the sheet is watertight elsewhere. Throws std::invalid_argument on
// topology OpenSubdiv rejects.
std::shared_ptr<const BaseTessellation> tessellateLimitSurface(const Texture& height,
                                                               const ControlMesh& cage,
                                                               Scheme scheme, double worldPerUv,
                                                               int rate);

// The `polygonal` truth of a mesh: the very triangles the rasteriser draws, each split
// uniformly into n^2 sub-triangles (n = rate x its longest UV edge in texels), displaced along
// the interpolated vertex normal. Every edge gets rate x its own length in points, made once
// and shared by the drawn triangles on it (a finer lattice's boundary snaps to them), so the
// sheet is watertight wherever the UVs are continuous (it opens at UV seams, as the real
// displaced asset does). `maxVertices` bounds the tessellation (all counts are lowered by one
// factor to fit).
// The vertices tessellateDrawnMesh makes at `rate` (an upper bound; only the map's size is
// read): what the scene's memory estimate counts before anything is built.
double drawnTruthVertices(const Texture& height, const BaseMesh& drawn, int rate);

// Refuses (InputError on truth.rate) a mesh's polygonal truth that would need more than the
// memory limit: every drawn edge split at rate points per texel of its UV length (a tiled
// floor, UVs 0..20, on a large map asks for millions of vertices), and at 2 x rate for the
// uncertainty. Planes and limit truths: nothing (their own estimates). Called by every
// command before any work (frame/view_memory.h checkViewMemory).
void checkMeshTruthMemory(const Scene& scene);

std::shared_ptr<const BaseTessellation> tessellateDrawnMesh(const Texture& height,
                                                            const BaseMesh& drawn,
                                                            double worldPerUv, int rate,
                                                            int64_t maxVertices = int64_t(1) << 26);

}  // namespace pgt
