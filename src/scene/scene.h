// A validated scene (the JSON scene file of docs/scenes.md "Scene file): height field, base plane,
// displacement (docs/model.md §3), camera (§4), methods (§6b) and truth settings (§5).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "heightfield/texture.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "methods/method.h"
#include "scene/camera.h"

namespace pgt {

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

struct Displacement {
    double scale = 0.05;   // s, UV units
    double bias = -0.025;  // b, UV units
};

enum class Projection { Orthographic, Pinhole };
// Orthographic framing: "plane", "fill" or "view" (CameraSpec::frame).
enum class Framing { Plane, Fill, View };

struct CameraSpec {
    Projection type = Projection::Orthographic;
    double theta = 60, phi = 0;  // orthographic view angle and azimuth, degrees
    // Orthographic framing: "plane" fits the whole plane and its relief; "fill" covers the
    // image with a plane region `fillSize` world units wide (every pixel sees the surface);
    // "view" uses viewHeight as given.
    Framing frame = Framing::Plane;
    double fillSize = 0;  // "fill": default half the plane (the whole tile if infinite)
    Vec3d target{0};
    double viewHeight = 0;
    Vec3d eye{0, -2, 1.5}, up{0, 0, 1};
    double fov = 45;
    int width = 512, height = 512;
    bool jitter = false;  // sample each pixel at a seeded random position (studies)
    uint32_t jitterSeed = 1;
};

enum class TruthGeometry { Grid, Triangles };

struct TruthSpec {
    int rate = 4;  // tessellation samples per texel per axis
    TruthGeometry geometry = TruthGeometry::Grid;
    bool uncertainty = true;  // also trace at 2 x rate and report the difference
    // `pgt render` of a plane: when the whole view's truth would need more than this, the
    // frame is traced in blocks, each over a tessellation of only what it sees.
    int memoryMb = 1536;
};

// A directional light (docs/model.md §5b): the direction toward it by the angles of an
// orthographic camera's view direction, (sin t cos p, sin t sin p, cos t) in world space (a
// plane's tangent space). A scene or view holds it as an optional: none, no shadows anywhere.
struct LightSpec {
    double theta = 45, phi = 0;  // degrees
};

// What changes between the views of one scene in a study or a fit: the camera, (s, b) and
// the light. Stages take it beside the Scene instead of a copy of the Scene (which owns the
// texels).
struct ViewSpec {
    CameraSpec camera;
    Displacement displacement;
    std::optional<LightSpec> light;
};

struct Scene {
    std::string file;          // the scene file's path (for messages and relative paths)
    nlohmann::json json;       // as written by the user
    Texture height;            // address mode set from the scene
    bool mipmaps = false;      // "heightmap": {"mipmaps": true}: height.mips is built
    std::string heightSource;  // file path or procedural name, for the summary
    std::string heightSha1;    // SHA-1 of the height image file ("" for procedural maps)
    BaseSurface base = PlaneBase{};
    // The plane, for what only a plane lattice has (windows, blocks, tiling); null otherwise.
    const PlaneBase* plane() const { return std::get_if<PlaneBase>(&base); }
    PlaneBase* plane() { return std::get_if<PlaneBase>(&base); }
    Displacement displacement;
    double worldPerUv() const { return pgt::worldPerUv(base); }
    // Read by every stage whatever the base: the UV range and back-face culling.
    UvExtent uvExtent;
    bool cullBackFaces = true;
    CameraSpec camera;
    std::optional<LightSpec> light;
    std::vector<MethodConfig> methods;
    TruthSpec truth;
    nlohmann::json sweep;  // the "sweep" block as written (validated by study/sweep.h)
    nlohmann::json fit;    // the "fit" block as written (validated by study/fit.h)
    ViewSpec view() const { return {camera, displacement, light}; }  // the scene's own view
};

// Reads and validates a scene file; throws InputError (file, field, value) on bad input,
// with line and column for malformed JSON.
Scene loadScene(const std::string& path);
// The scene file's words for the enums.
std::string toString(MeshTruth truth);
std::string toString(Projection projection);
std::string toString(Framing framing);
// Validates a scene given as JSON; `file` is used for messages and relative paths.
Scene parseScene(const nlohmann::json& json, const std::string& file);

// The camera of a view of a scene, with an orthographic camera framing the whole plane and
// its relief slab (z in l*[b, s+b]) unless a view height is given.
Camera makeCamera(const Scene& scene, const ViewSpec& view);
inline Camera makeCamera(const Scene& scene) { return makeCamera(scene, scene.view()); }

// The scene as pgt understood it, seen from `view` (summary.json, a study's identity).
nlohmann::json resolvedSceneJson(const Scene& scene, const ViewSpec& view);
inline nlohmann::json resolvedSceneJson(const Scene& scene) {
    return resolvedSceneJson(scene, scene.view());
}

}  // namespace pgt
