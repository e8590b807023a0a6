// The polygon mesh the rasteriser draws for a curved base: the control mesh refined
// `levels` times by OpenSubdiv (bilinear, Catmull-Clark or Loop), vertices moved to the limit
// surface for the smooth schemes, fan-triangulated, one vertex per (position, UV) pair, with
// vertex normals and Lengyel FGED 2 Listing 7.4 tangent frames.
#pragma once

#include <string>

#include "mesh/base_mesh.h"
#include "mesh/control_mesh.h"

namespace pgt {

enum class Scheme { Bilinear, Catmark, Loop };
std::string toString(Scheme s);

struct TangentFrameStats {
    int64_t degenerateUvTriangles = 0;  // |du x dv| ~ 0: no tangent from this triangle
    int64_t fallbackTangents = 0;       // vertices left without a usable tangent sum
    int64_t mirroredVertices = 0;       // handedness w = -1
};

// Lengyel FGED 2 Listing 7.4: per-triangle T and B from positions and UVs (Eq. 7.37) accumulated
// per vertex, Gram-Schmidt against the vertex normal (Eq. 7.38), handedness w = sign(dot(cross(t,
// b), n)). Triangles whose UV determinant is (near) zero add nothing (counted); a vertex with no
// usable tangent gets one perpendicular to n (counted). Fills mesh.vertices[*].tangent (unit),
// bitangent (= cross(n, t) * w, Eq. 7.40) and returns w per vertex.
std::vector<float> computeTangentFrames(BaseMesh& mesh, TangentFrameStats* stats);

struct RefinedMesh {
    BaseMesh mesh;
    std::vector<float> handedness;  // w per vertex
    TangentFrameStats frames;
};

// Throws std::invalid_argument on topology OpenSubdiv rejects (e.g. Loop on non-triangles).
RefinedMesh refineToTriangles(const ControlMesh& cage, Scheme scheme, int levels);

}  // namespace pgt
