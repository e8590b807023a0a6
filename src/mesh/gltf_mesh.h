// glTF 2.0 meshes (.gltf with external or embedded buffers, .glb), read with tinygltf: one
// primitive's positions, normals, texture coordinates and tangents as the asset stores them,
// under its node's transform, turned into pgt's conventions (docs/model.md §2 "glTF assets"):
// glTF's +Y up becomes pgt's +Z up, glTF's v (down the image) becomes pgt's v = 1 - v.
#pragma once

#include <string>

#include "mesh/control_mesh.h"
#include "mesh/refine.h"

namespace pgt {

// Which primitive: a mesh by index or name, a primitive of it, the TEXCOORD set, and the
// node whose transform places it, by index or name (-1: the first node that instances the
// mesh, else none). A node given without a mesh brings the mesh it places.
struct GltfSelection {
    int mesh = 0;
    std::string meshName;  // when set, chosen over `mesh`
    bool meshGiven = false;
    int primitive = 0;
    bool primitiveGiven = false;  // else a mesh of several primitives gets a notice on stderr
    int uvSet = 0;
    int node = -1;
    std::string nodeName;  // when set, chosen over `node`
};

// The frames the drawn mesh carries: the asset's TANGENT (MikkTSpace where it has none),
// MikkTSpace always, or pgt's own (Lengyel FGED 2 Listing 7.4, as on OBJ meshes).
enum class MeshFrames { Asset, MikkTSpace, Pgt };
std::string toString(MeshFrames frames);

struct GltfMesh {
    RefinedMesh drawn;        // the primitive's triangles with their frames, in world space
    ControlMesh cage;         // the same triangles, positions welded: the limit truth's cage
    std::string framesUsed;   // "asset", "mikktspace" or "pgt"
    std::string description;  // e.g. mesh 0 "Sphere" primitive 0, node 0
};

// Reads and checks everything before building: the file's size (at most 1 GiB), every
// accessor's range inside its buffer, every index against the vertex count, finite values,
// unit-able normals and tangents, the node graph (no cycles), a buffer uri that leaves the
// asset's folder. Bad input throws InputError(sceneFile, field, path, what is wrong).
GltfMesh loadGltfMesh(const std::string& path, const GltfSelection& which, MeshFrames frames,
                      const std::string& sceneFile, const std::string& field);

}  // namespace pgt
