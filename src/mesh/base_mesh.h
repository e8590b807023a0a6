// The mesh the rasteriser draws: vertices with UVs and a per-vertex tangent frame, and
// triangles over them; the plane of docs/model.md §2 as such a mesh. Built by mesh/refine.h for
// curved bases, drawn by raster/raster.h.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace pgt {

struct BaseVertex {
    Vec3d position;
    Vec2d uv;
    Vec3d tangent, bitangent, normal;  // per-vertex frame (T along dS/du, B along dS/dv)
    double handedness = 1.0;           // Lengyel FGED 2 Listing 7.4's w: sign of det(tangent frame)
};

struct BaseMesh {
    std::vector<BaseVertex> vertices;
    std::vector<uint32_t> indices;  // triangles, counter-clockwise seen from the front (+N)
};

// The plane of docs/model.md §2 as two triangles; `tilesAround` > 0 extends it by that many
// whole tiles on every side (an infinite plane's visible part), UVs continuing outward.
BaseMesh makePlaneMesh(Vec3d center, double size, double tiling, int tilesAround = 0);

}  // namespace pgt
