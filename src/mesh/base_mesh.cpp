// The plane as a base mesh (mesh/base_mesh.h).
#include "mesh/base_mesh.h"

namespace pgt {

BaseMesh makePlaneMesh(Vec3d center, double size, double tiling, int tilesAround) {
    BaseMesh m;
    const double k = tilesAround;
    const double h = size / 2 + k * size;
    const Vec3d t(1, 0, 0), b(0, 1, 0), n(0, 0, 1);
    const Vec2d corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& c : corners)
        m.vertices.push_back({center + Vec3d((c.x * 2 - 1) * h, (c.y * 2 - 1) * h, 0.0),
                              (c * (2 * k + 1) - k) * tiling, t, b, n});
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

}  // namespace pgt
