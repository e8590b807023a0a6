// MikkTSpace tangent frames (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited";
// the algorithm glTF 2.0 prescribes for assets without TANGENT), written from its
// description: per triangle the direction of increasing u, signed by the triangle's UV
// orientation; per vertex the corner-angle-weighted sum of those directions, each projected
// into the vertex normal's plane, over the triangles that share the vertex (same position,
// normal and UV) and the same orientation. docs/model.md §2 says what pgt does with it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace pgt {

struct MikkInput {
    const std::vector<Vec3d>& positions;
    const std::vector<Vec3d>& normals;  // unit
    const std::vector<Vec2d>& uvs;      // v up (the image's bottom row at v = 0)
    const std::vector<uint32_t>& triangles;
};

struct MikkFrames {
    // Per corner of `triangles`: the unit tangent and the sign w (bitangent = w cross(n, t)).
    std::vector<Vec3d> tangent;
    std::vector<float> sign;
    int64_t degenerateUvTriangles = 0;  // zero UV area: no direction of their own
    int64_t fallbackTangents = 0;       // corners no triangle gave a direction
};

// Frames per triangle corner: corners of one vertex in triangles of the other UV orientation
// (a mirror seam) get their own tangent and sign, so a caller splits such vertices.
MikkFrames mikkTSpace(const MikkInput& in);

}  // namespace pgt
