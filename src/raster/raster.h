// CPU rasteriser of the base mesh (MODEL.md §6): what the GPU's parallax-mapped draw sees.
// Pixel centres, the top-left fill rule, a depth test, near-plane clipping, and
// perspective-correct interpolation of UV, position and the tangent frame. Per covered
// pixel it gives uv0 and the tangent-space view vector V.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "mesh/base_mesh.h"
#include "scene/camera.h"

namespace pgt {

// How many tiles around the central one an infinite plane needs so that every pixel ray
// of `camera` that meets the plane z = center.z meets it inside (at most `cap`).
int tilesToCover(const Camera& camera, Vec3d center, double size, int cap = 64);

struct Fragment {
    bool covered = false;
    Vec2d uv0{0};
    Vec3d position{0};
    Vec3d viewTangent{0};  // unit V in tangent space (V.T, V.B, V.N); methods round to float
    // V in the exact frame of the drawn surface: T along dS/du, B along dS/dv of the drawn
    // triangle, N the interpolated normal the truth displaces along, orthonormalised
    // (MODEL.md §2). Equal to viewTangent on a plane; false where the triangle's UVs are
    // degenerate (then it repeats viewTangent).
    Vec3d viewTangentExact{0};
    bool exactFrame = false;
};

struct RasterOptions {
    bool cullBackFaces = true;
};

struct RasterStats {
    int64_t covered = 0;
    int64_t noExactFrame = 0;  // covered pixels on triangles with degenerate UVs
    int64_t trianglesDrawn = 0;
    int64_t trianglesCulled = 0;
};

Image2D<Fragment> rasterize(const BaseMesh& mesh, const Camera& camera,
                            const RasterOptions& options, RasterStats* stats = nullptr);

}  // namespace pgt
