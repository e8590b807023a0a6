// MikkTSpace (mesh/mikktspace.h), written anew from Mikkelsen's description.
//
// Differences from the reference implementation, none of which the committed Blender assets
// exercise (tests/mesh_gltf_test.cpp checks agreement there): a vertex's corners of one
// orientation form one group even where its fan is not connected through shared edges, and
// a triangle with zero UV area takes its vertex's group of either orientation.
#include "mesh/mikktspace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "core/interrupt.h"

namespace pgt {

namespace {

// The weld key: a vertex is the same vertex wherever position, normal and UV are equal
// (-0 and +0 are one value, as float comparison has it).
using WeldKey = std::array<double, 8>;
WeldKey weldKey(const MikkInput& in, uint32_t v) {
    const Vec3d& p = in.positions[v];
    const Vec3d& n = in.normals[v];
    const Vec2d& t = in.uvs[v];
    WeldKey k{p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y};
    for (double& x : k) x += 0.0;  // -0 -> +0
    return k;
}

Vec3d projectOut(const Vec3d& v, const Vec3d& n) { return v - n * glm::dot(n, v); }

Vec3d unitOrZero(const Vec3d& v) {
    const double len = glm::length(v);
    return len > std::numeric_limits<float>::min() ? v / len : Vec3d(0);
}

// Any unit vector perpendicular to n (a corner nothing gave a direction).
Vec3d perpendicular(const Vec3d& n) {
    const Vec3d axis = std::fabs(n.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
    return glm::normalize(projectOut(axis, n));
}

// Per triangle: the unit direction of increasing u in its plane and its UV orientation (+1
// preserving, -1 flipping, 0 without UV area, direction zero). Returns how many have no area.
int64_t triangleDirections(const MikkInput& in, std::vector<Vec3d>& dirU,
                           std::vector<int8_t>& orient) {
    const size_t nTri = in.triangles.size() / 3;
    dirU.assign(nTri, Vec3d(0));
    orient.assign(nTri, 0);
    int64_t degenerate = 0;
    for (size_t t = 0; t < nTri; ++t) {
        if ((t & 0xffff) == 0) throwIfCancelled();  // Ctrl-C in Python: millions of triangles
        const uint32_t* i = &in.triangles[3 * t];
        const Vec3d d1 = in.positions[i[1]] - in.positions[i[0]];
        const Vec3d d2 = in.positions[i[2]] - in.positions[i[0]];
        const Vec2d s1 = in.uvs[i[1]] - in.uvs[i[0]], s2 = in.uvs[i[2]] - in.uvs[i[0]];
        const double area2 = s1.x * s2.y - s1.y * s2.x;
        if (!(std::fabs(area2) > std::numeric_limits<float>::min())) {
            ++degenerate;
            continue;
        }
        orient[t] = area2 > 0 ? 1 : -1;
        dirU[t] = unitOrZero(d1 * s2.y - d2 * s1.y) * double(orient[t]);
    }
    return degenerate;
}

}  // namespace

MikkFrames mikkTSpace(const MikkInput& in) {
    const size_t corners = in.triangles.size(), nTri = corners / 3;
    // Welded vertex per corner.
    std::map<WeldKey, uint32_t> ids;
    std::vector<uint32_t> weld(corners);
    for (size_t c = 0; c < corners; ++c)
        weld[c] = ids.emplace(weldKey(in, in.triangles[c]), uint32_t(ids.size())).first->second;

    MikkFrames out;
    std::vector<Vec3d> dirU;
    std::vector<int8_t> orient;
    out.degenerateUvTriangles = triangleDirections(in, dirU, orient);

    // Per (welded vertex, orientation): the angle-weighted sum of the projected directions.
    std::vector<Vec3d> sum(2 * ids.size(), Vec3d(0));
    auto group = [&](size_t c, int o) { return 2 * size_t(weld[c]) + (o > 0 ? 0 : 1); };
    for (size_t t = 0; t < nTri; ++t) {
        if (orient[t] == 0) continue;
        for (int k = 0; k < 3; ++k) {
            const size_t c = 3 * t + size_t(k);
            const Vec3d& n = in.normals[in.triangles[c]];
            const Vec3d& p = in.positions[in.triangles[c]];
            const Vec3d e1 = unitOrZero(
                projectOut(in.positions[in.triangles[3 * t + size_t((k + 2) % 3)]] - p, n));
            const Vec3d e2 = unitOrZero(
                projectOut(in.positions[in.triangles[3 * t + size_t((k + 1) % 3)]] - p, n));
            const double angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0));
            sum[group(c, orient[t])] += unitOrZero(projectOut(dirU[t], n)) * angle;
        }
    }

    out.tangent.resize(corners);
    out.sign.resize(corners);
    for (size_t c = 0; c < corners; ++c) {
        int o = orient[c / 3];
        // No UV area: the vertex's preserving group if it has one, else its flipping one.
        if (o == 0) o = glm::dot(sum[group(c, 1)], sum[group(c, 1)]) > 0 ? 1 : -1;
        Vec3d t = unitOrZero(sum[group(c, o)]);
        if (t == Vec3d(0)) {
            t = perpendicular(in.normals[in.triangles[c]]);
            ++out.fallbackTangents;
        }
        out.tangent[c] = t;
        out.sign[c] = float(o);
    }
    return out;
}

}  // namespace pgt
