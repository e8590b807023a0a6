// The base surface the relief displaces (docs/model.md §2): a plane or a mesh (a control mesh
// refined by OpenSubdiv, or a glTF primitive), and everything a stage asks of it, in one place:
// its scene entry ("base"), its JSON, the mesh the rasteriser draws, its UV extent, frames,
// relief box and world scale. Each is one std::visit over the alternatives, so a new kind is
// an alternative here, its overloads in this file's functions, and its tessellation in
// truth/ (truth/builder.cpp, truth/tessellation.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>

#include "core/json_fields.h"
#include "heightfield/texture.h"
#include "mesh/base_mesh.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "scene/camera.h"

namespace pgt {

struct Scene;

// The UV range a base's texture coordinates span: [0, tiling]^2 for a plane, the bounding
// box of the cage's UVs for a mesh (a cylinder with tiling [2, 1]: [0, 2] x [0, 1]).
// LearnOpenGL's `discard_outside` discards uv' outside it.
struct UvExtent {
    Vec2d lo{0, 0}, hi{1, 1};
    UvExtent() = default;
    UvExtent(double tiling) : hi(tiling, tiling) {}  // a plane's [0, tiling]^2 (implicit)
    UvExtent(Vec2d lo_, Vec2d hi_) : lo(lo_), hi(hi_) {}
    bool contains(double u, double v) const {  // NaN is inside: LearnOpenGL's test is x > 1 ...
        return !(u > hi.x || v > hi.y || u < lo.x || v < lo.y);
    }
};

struct PlaneBase {
    double size = 1.0;      // side L in world units
    double tiling = 1.0;    // UV range [0, tiling]^2
    Vec3d center{0, 0, 0};  // plane centre; the plane lies in z = center.z
    bool infinite = false;  // the tile repeats forever in x and y (repeat, integer tiling)
    double worldPerUv() const { return size / tiling; }  // l (docs/model.md §2)
};

// The truth's vertex lattice over a plane at `rate` samples per texel per axis (docs/model.md §5):
// ceil(rate x map size x tiling) segments per axis across the tile. The scene's size limit,
// the memory estimate, the block planner and the tessellation all count with this one
// formula. Counts are doubles: a lattice too large for an int is refused, not wrapped.
struct PlaneLattice {
    double nu = 1, nv = 1;  // segments across the whole tile
    double tiling = 1;
    PlaneLattice(const PlaneBase& plane, const Texture& height, int rate)
        : nu(segments(rate, height.width, plane.tiling)),
          nv(segments(rate, height.height, plane.tiling)),
          tiling(plane.tiling) {}
    double vertices() const { return (nu + 1) * (nv + 1); }
    // The whole cells covering UV [lo, hi] on one axis (segments `n` across the tile): the
    // first cell's index and the count (a window's lattice is the tile's, cut).
    struct Span {
        double first = 0, count = 1;
    };
    Span span(double lo, double hi, double n) const {
        const double perUv = n / tiling, first = std::floor(lo * perUv);
        return {first, std::max(1.0, std::ceil(hi * perUv) - first)};
    }
    double vertices(Vec2d lo, Vec2d hi) const {
        return (span(lo.x, hi.x, nu).count + 1) * (span(lo.y, hi.y, nv).count + 1);
    }
    // 1e-9 absorbs the rounding of rate x size x tiling (a tiling of 0.3 on 10 texels).
    static double segments(int rate, int texels, double tiling) {
        return std::max(1.0, std::ceil(double(rate) * texels * tiling - 1e-9));
    }
};

// What a mesh's truth displaces: "polygonal", the drawn mesh along its vertex normals (the
// method's own error); "limit", the OpenSubdiv limit surface along its exact normal (the
// asset as meant: adds faceting and frame error).
enum class MeshTruth { Polygonal, Limit };

// A curved base: a control mesh refined by OpenSubdiv, or a glTF primitive drawn as the
// asset has it (its triangles are the cage of its limit truth).
struct MeshBase {
    std::string source;  // "cube", "cylinder", "torus", the OBJ or the glTF path
    bool gltf = false;
    std::string part;            // glTF: which mesh and primitive (mesh 0 "Sphere" primitive 0)
    std::string frames = "pgt";  // the drawn frames: "asset", "mikktspace" or "pgt"
    Scheme scheme = Scheme::Catmark;
    int refine = 2;  // levels for the mesh the rasteriser draws
    MeshTruth truthSurface = MeshTruth::Polygonal;
    double worldPerUv = 0;                     // l: from the scene, else sqrt(world area / UV area)
    std::shared_ptr<const ControlMesh> cage;   // as read
    std::shared_ptr<const RefinedMesh> drawn;  // built at load time
};

// The base surface the relief displaces: a plane lattice or a subdivision mesh. Every stage
// asks it through the functions below (each a std::visit over the alternatives), never by
// kind: a third kind is one more alternative and its overload in each of them. Plane-only
// capabilities (truth windows and blocks, the infinite tiling) go through Scene::plane().
using BaseSurface = std::variant<PlaneBase, MeshBase>;

const char* baseType(const BaseSurface& base);  // "plane", "mesh"
double worldPerUv(const BaseSurface& base);     // l (docs/model.md §2)
UvExtent uvExtentOf(const BaseSurface& base);   // the UV range its coordinates span
// Whether its drawn per-vertex tangent frames can differ from the exact frame of the drawn
// surface, so that each method also runs with the exact frame (docs/model.md §2): meshes.
bool framesCanDiffer(const BaseSurface& base);
// The box holding the base displaced by z in [zLo, zHi] world units along its normals (what
// an orthographic "plane" framing fits).
void reliefBox(const BaseSurface& base, double zLo, double zHi, Vec3d& lo, Vec3d& hi);

// "base" of a scene file (docs/scenes.md): a plane (size, tiling, centre, infinite), a mesh or
// a glTF asset, the UV extent and culling; a mesh's drawn faces checked against the memory
// limit before it is refined.
void parseBaseSurface(Scene& s, JsonFields& root);
// summary.json's scene.base (the type and its settings as pgt understood them) and
// scene.drawn_mesh (a mesh's refined triangles and its frames' statistics; null for a plane).
nlohmann::json baseJson(const Scene& s);
nlohmann::json drawnMeshJson(const BaseSurface& base);
// The mesh the rasteriser draws: a plane's two triangles per tile (as many tiles as the
// camera sees of an infinite plane), a mesh's refined triangles.
BaseMesh drawnBaseMesh(const BaseSurface& base, const Camera& camera);

}  // namespace pgt
