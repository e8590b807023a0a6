// A validated scene (the JSON scene file of docs/scenes.md "Scene file): height field, base plane,
// displacement (docs/model.md §3), camera (§4), methods (§6b) and truth settings (§5).
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/json_fields.h"
#include "heightfield/texture.h"
#include "methods/method.h"
#include "scene/base_surface.h"
#include "scene/camera.h"

namespace pgt {

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
// For the scene's parsers: a [x, y, z] field, and a file the scene names (absolute as written,
// else relative to the scene file's folder).
Vec3d vec3(JsonFields& f, const std::string& key, double lo = -1e9, double hi = 1e9);
// A block of the scene as the user wrote it (null for scenes built in code).
nlohmann::json givenBlock(const Scene& s, const char* key);
std::filesystem::path besideScene(const Scene& s, const std::string& rel);

// The camera of a view of a scene, with an orthographic camera framing the whole plane and
// its relief slab (z in l*[b, s+b]) unless a view height is given.
Camera makeCamera(const Scene& scene, const ViewSpec& view);
inline Camera makeCamera(const Scene& scene) { return makeCamera(scene, scene.view()); }
// The view's directional light (docs/model.md §5b): the unit world direction toward it, none
// without one. The truth casts shadow rays along it (TruthSurface's traces); the rasteriser
// gives each fragment its tangent-space direction (RasterOptions::light).
std::optional<Vec3d> lightToward(const ViewSpec& view);

// The scene as pgt understood it, seen from `view` (summary.json, a study's identity).
nlohmann::json resolvedSceneJson(const Scene& scene, const ViewSpec& view);
inline nlohmann::json resolvedSceneJson(const Scene& scene) {
    return resolvedSceneJson(scene, scene.view());
}

}  // namespace pgt
