// Control meshes for curved bases (docs/model.md §2): polygons with face-varying UVs, from the
// built-in cages (cube, cylinder, torus) or an OBJ file, and the world length per UV unit.
#pragma once

#include <string>
#include <vector>

#include "core/math.h"

namespace pgt {

struct ControlMesh {
    std::vector<Vec3d> positions;
    std::vector<int> faceSizes;  // vertices per face
    std::vector<int> faceVerts;  // position index per face corner
    std::vector<Vec2d> uvs;      // face-varying UV values
    std::vector<int> faceUvs;    // UV index per face corner
    std::string sourceSha1;      // SHA-1 of the OBJ file's text ("" for built-in cages)
    int numFaces() const { return int(faceSizes.size()); }
};

// A cube of side `size` centred at the origin: 8 corners, 6 quads, each face mapped to the
// whole UV square [0, tiling]^2 (seams on every edge).
ControlMesh makeCubeCage(double size, double tiling);
// An open tube around +z: radius, height, `segments` quads around; u runs around (seam at
// +x, u = 0 and u = tilingU on the two sides), v along the height.
ControlMesh makeCylinderCage(double radius, double height, int segments, double tilingU,
                             double tilingV);
// A torus around +z: major radius R, minor radius r, segU x segV quads; u around the main
// circle, v around the tube, seams where either wraps.
ControlMesh makeTorusCage(double majorRadius, double minorRadius, int segU, int segV,
                          double tilingU, double tilingV);
// Positions, texture coordinates and polygons of an OBJ file (tinyobjloader); faces without
// texture coordinates are an error naming the file and field.
ControlMesh loadObjMesh(const std::string& path, const std::string& sceneFile,
                        const std::string& field);

// sqrt(world area / UV area) over the mesh's faces (fan-triangulated): docs/model.md §2's
// default l. Throws std::invalid_argument when the UV area is zero.
double worldPerUvFromAreas(const ControlMesh& mesh);

}  // namespace pgt
