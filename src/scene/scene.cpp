// Scene file parsing and validation; the camera a scene describes.
#include "scene/scene.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/format.h"
#include "core/json_fields.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "core/overloaded.h"
#include "heightfield/heightfield.h"
#include "heightfield/mipmaps.h"
#include "mesh/gltf_mesh.h"
#include "methods/config.h"

namespace pgt {

namespace fs = std::filesystem;

Scene loadScene(const std::string& path) { return parseScene(readJsonFile(path), path); }

namespace {

Vec3d vec3(JsonFields& f, const std::string& key, double lo = -1e9, double hi = 1e9) {
    auto v = f.numbers(key, 3, lo, hi);
    return {v[0], v[1], v[2]};
}

// A file the scene names: absolute as written, else relative to the scene file's folder.
fs::path besideScene(const Scene& s, const std::string& rel) {
    return fs::path(rel).is_absolute() ? fs::path(rel) : fs::path(s.file).parent_path() / rel;
}

// A height image named by the scene: its header is read while parsing, its pixels only
// after every other check has passed (a huge map is refused before it is decoded).
struct PendingImage {
    std::string path;
    int channel = 0;
    bool channelGiven = false;
};

void parseHeightmap(Scene& s, JsonFields& root, PendingImage& pending) {
    const Json& hm = root.raw("heightmap");
    JsonFields f(hm, s.file, "heightmap");
    if (f.has("file") == f.has("procedural"))
        throw InputError(s.file, "heightmap", shortDump(hm),
                         "give exactly one of \"file\" or \"procedural\"");
    s.mipmaps = f.boolean("mipmaps", false);
    if (f.has("file")) {
        std::string rel = f.string("file");
        bool channelGiven = f.has("channel");
        int channel = f.integer("channel", 0, 0, 1023);
        f.finish();
        const fs::path p = besideScene(s, rel);
        HeightImageHeader header = probeHeightImage(p.string(), channel, s.file, "heightmap");
        s.height.width = header.width;
        s.height.height = header.height;
        pending = {p.string(), channel, channelGiven};
        s.heightSource = rel;
        s.heightSha1 = fileSha1(p.string());
    } else {
        s.height = makeProceduralHeight(hm, s.file, "heightmap");
        s.heightSource = "procedural:" + hm.at("procedural").get<std::string>();
    }
}

// Refining, the drawn mesh's frames, its truth sheet and Embree's build took 1.1 KB per drawn
// face (measured: a 256 x 256-quad OBJ at refine 2, 2^20 faces, 1.14 GB above the process's
// base); 1200 bytes a face estimates it before anything is refined or built.
constexpr double kBytesPerDrawnFace = 1200;

Scheme schemeField(JsonFields& f, const std::string& fallback) {
    const std::string scheme = f.choice("scheme", {"bilinear", "catmark", "loop"}, fallback);
    return scheme == "bilinear" ? Scheme::Bilinear
           : scheme == "loop"   ? Scheme::Loop
                                : Scheme::Catmark;
}

MeshTruth truthSurfaceField(JsonFields& f) {
    return f.choice("truth_surface", {"polygonal", "limit"}, "polygonal") == "limit"
               ? MeshTruth::Limit
               : MeshTruth::Polygonal;
}

// The control mesh of a mesh base: a built-in cage or an OBJ file beside the scene.
ControlMesh readCage(const Scene& s, JsonFields& f, MeshBase& m) {
    if (f.has("cage") == f.has("file"))
        f.fail(
            "cage",
            "a mesh base needs exactly one of \"cage\" (cube, cylinder, torus) or \"file\" (OBJ)");
    std::vector<double> tiling =
        f.has("tiling") ? f.numbers("tiling", 2, 1e-6, 1e6) : std::vector<double>{1.0, 1.0};
    if (f.has("file")) {
        std::string rel = f.string("file");
        const fs::path p = besideScene(s, rel);
        m.source = rel;
        return loadObjMesh(p.string(), s.file, "base.file");
    }
    m.source = f.choice("cage", {"cube", "cylinder", "torus"}, "cube");
    if (m.source == "cube") return makeCubeCage(f.number("size", 1.0, 1e-6, 1e9), tiling[0]);
    if (m.source == "cylinder")
        return makeCylinderCage(f.number("radius", 0.5, 1e-6, 1e9),
                                f.number("height", 1.0, 1e-6, 1e9),
                                f.integer("segments", 16, 3, 4096), tiling[0], tiling[1]);
    std::vector<int> seg =
        f.has("segments") ? f.integers("segments", 2, 3, 4096) : std::vector<int>{16, 8};
    return makeTorusCage(f.number("major_radius", 0.5, 1e-6, 1e9),
                         f.number("minor_radius", 0.2, 1e-6, 1e9), seg[0], seg[1], tiling[0],
                         tiling[1]);
}

void parseMeshBase(const Scene& s, JsonFields& f, MeshBase& m) {
    const ControlMesh cage = readCage(s, f, m);
    // Bound the work before refining: the drawn mesh has about faces x 4^refine faces (a
    // fuzzed torus at refine 6 took 12 s to parse); 2^24 faces is far beyond any study.
    if (cage.numFaces() > (1 << 20))
        f.fail(f.has("file") ? "file" : "segments", "the control mesh has more than 2^20 faces");
    m.scheme = schemeField(f, "catmark");
    m.refine = f.integer("refine", 2, 0, 6);
    int maxFaceSize = *std::max_element(cage.faceSizes.begin(), cage.faceSizes.end());
    double refinedFaces = double(cage.numFaces()) * (m.refine > 0 ? maxFaceSize : 1) *
                          std::pow(4.0, std::max(0, m.refine - 1));
    if (refinedFaces > double(1 << 24))
        f.fail("refine", "would draw about " + std::to_string(int64_t(refinedFaces)) +
                             " faces (more than 2^24): lower refine or the cage's segments");
    checkMemory(refinedFaces * kBytesPerDrawnFace, s.file, "base.refine", std::to_string(m.refine),
                "a mesh of " + std::to_string(cage.numFaces()) + " faces refined " +
                    std::to_string(m.refine) + " times (about " +
                    std::to_string(int64_t(refinedFaces)) + " drawn faces)");
    m.truthSurface = truthSurfaceField(f);
    try {
        m.drawn = std::make_shared<RefinedMesh>(refineToTriangles(cage, m.scheme, m.refine));
        m.cage = std::make_shared<ControlMesh>(cage);
        m.worldPerUv =
            f.has("world_per_uv") ? f.number("world_per_uv", 1e-9, 1e9) : worldPerUvFromAreas(cage);
    } catch (const std::invalid_argument& e) {
        f.fail(f.has("file") ? "file" : "cage", e.what());
    }
}

// A glTF base: the primitive as the asset draws it (docs/scenes.md "glTF assets").
void parseGltfBase(const Scene& s, JsonFields& f, MeshBase& m) {
    m.gltf = true;
    m.source = f.string("file");
    const fs::path p = besideScene(s, m.source);
    GltfSelection which;
    // "mesh" and "node": an index or a name.
    auto indexOrName = [&](const char* key, int& index, std::string& name) {
        if (!f.has(key)) return false;
        if (!f.raw(key).is_string()) {
            index = f.integer(key, 0, 1 << 30);
        } else if ((name = f.string(key)).empty()) {
            f.fail(key, "an empty name");
        }
        return true;
    };
    which.meshGiven = indexOrName("mesh", which.mesh, which.meshName);
    indexOrName("node", which.node, which.nodeName);
    which.primitive = f.integer("primitive", 0, 0, 1 << 30);
    which.primitiveGiven = f.has("primitive");
    which.uvSet = f.integer("uv", 0, 0, 1 << 20);
    const std::string frames = f.choice("frames", {"asset", "mikktspace", "pgt"}, "asset");
    const MeshFrames kind = frames == "pgt"          ? MeshFrames::Pgt
                            : frames == "mikktspace" ? MeshFrames::MikkTSpace
                                                     : MeshFrames::Asset;
    m.scheme = schemeField(f, "loop");
    m.refine = 0;  // drawn as the asset has it
    m.truthSurface = truthSurfaceField(f);
    GltfMesh asset = loadGltfMesh(p.string(), which, kind, s.file, "base.file");
    const double faces = double(asset.drawn.mesh.indices.size() / 3);
    checkMemory(faces * kBytesPerDrawnFace, s.file, "base.file", m.source,
                "a glTF primitive of " + std::to_string(int64_t(faces)) + " triangles");
    m.part = asset.description;
    m.frames = asset.framesUsed;
    try {
        m.worldPerUv = f.has("world_per_uv") ? f.number("world_per_uv", 1e-9, 1e9)
                                             : worldPerUvFromAreas(asset.cage);
    } catch (const std::invalid_argument& e) {
        f.fail("file", e.what());
    }
    m.drawn = std::make_shared<RefinedMesh>(std::move(asset.drawn));
    m.cage = std::make_shared<ControlMesh>(std::move(asset.cage));
}

// "base": a plane (size, tiling, centre, infinite), a mesh or a glTF asset; the UV extent
// and culling.
void parseBase(Scene& s, JsonFields& root) {
    JsonFields f(root.raw("base"), s.file, "base");
    std::string type = f.choice("type", {"plane", "mesh", "gltf"}, "plane");
    if (type == "mesh" || type == "gltf") {
        MeshBase m;
        type == "mesh" ? parseMeshBase(s, f, m) : parseGltfBase(s, f, m);
        s.base = std::move(m);
    } else {
        PlaneBase p;
        p.size = f.number("size", 1.0, 1e-6, 1e9);
        p.tiling = f.number("tiling", 1.0, 1e-6, 1e6);
        if (f.has("center")) p.center = vec3(f, "center");
        p.infinite = f.boolean("infinite", false);
        if (p.infinite) {
            if (s.height.address != Address::Repeat)
                f.fail("infinite",
                       "an infinite plane repeats its tile: needs \"address\": \"repeat\"");
            // Whole up to the 1e-9 a decimal written in JSON can be off by.
            if (std::fabs(p.tiling - std::round(p.tiling)) > 1e-9)
                f.fail("infinite", "an infinite plane needs a whole-number base.tiling");
        }
        s.base = p;
    }
    s.cullBackFaces = f.boolean("cull_back_faces", true);
    s.uvExtent = uvExtentOf(s.base);
    f.finish();
}

// "camera": orthographic (view angles and framing) or pinhole (eye, target, up, fov).
void parseCamera(Scene& s, JsonFields& root) {
    JsonFields f(root.raw("camera"), s.file, "camera");
    CameraSpec& c = s.camera;
    c.type = f.choice("type", {"orthographic", "pinhole"}, "orthographic") == "pinhole"
                 ? Projection::Pinhole
                 : Projection::Orthographic;
    auto res = f.integers("resolution", 2, 1, 16384);
    c.width = res[0];
    c.height = res[1];
    if (double(c.width) * c.height > double(1 << 26)) f.fail("resolution", "more than 2^26 pixels");
    c.jitter = f.choice("samples", {"centre", "jittered"}, "centre") == "jittered";
    c.jitterSeed = uint32_t(f.integer("seed", 1, 0, 2147483647));
    if (c.type == Projection::Orthographic) {
        c.theta = f.number("theta", 0.0, 90.0);
        const PlaneBase* plane = s.plane();
        if (!plane && f.has("frame") && f.string("frame") == "fill")
            f.fail("frame", "\"fill\" frames a plane; this base is framed whole (\"plane\")");
        c.phi = f.number("phi", 0.0, -360.0, 360.0);
        c.frame = f.choice("frame", {"plane", "fill"}, "plane") == "fill" ? Framing::Fill
                                                                          : Framing::Plane;
        if (plane)
            c.fillSize =
                f.number("fill_size", plane->infinite ? plane->size : plane->size / 2, 1e-9, 1e9);
        if (f.has("view_height")) {
            if (f.has("frame")) f.fail("view_height", "give either \"frame\" or \"view_height\"");
            c.frame = Framing::View;
            c.viewHeight = f.number("view_height", 1e-9, 1e9);
        }
        // Default: the plane's centre; other bases the origin (where the built-in cages sit).
        c.target = f.has("target") ? vec3(f, "target") : plane ? plane->center : Vec3d(0);
    } else {
        c.eye = vec3(f, "eye");
        c.target = vec3(f, "target");
        c.up = f.has("up") ? vec3(f, "up") : Vec3d(0, 0, 1);
        c.fov = f.number("fov", 45.0, 1e-3, 179.0);
        Vec3d fwd = c.target - c.eye;
        // Degenerate views: an eye on its target, an up vector within 1e-9 rad of the view
        // direction (either would leave the camera frame undefined).
        if (glm::length(fwd) < 1e-12) f.fail("target", "equals eye");
        if (glm::length(glm::cross(glm::normalize(fwd), c.up)) < 1e-9)
            f.fail("up", "is parallel to the viewing direction");
    }
    f.finish();
}

// "light": {"theta", "phi"}: a directional light (docs/model.md §5b).
void parseLight(Scene& s, JsonFields& root) {
    if (!root.has("light")) return;
    JsonFields f(root.raw("light"), s.file, "light");
    s.light = LightSpec{f.number("theta", 0.0, 90.0), f.number("phi", 0.0, -360.0, 360.0)};
    f.finish();
}

// "truth": rate, geometry, uncertainty, memory budget; a plane's vertex bound. (The memory a
// mesh's truth needs is truth/'s to estimate: checkMeshTruthMemory, before any work.)
void parseTruth(Scene& s, JsonFields& root) {
    if (root.has("truth")) {
        JsonFields f(root.raw("truth"), s.file, "truth");
        s.truth.rate = f.integer("rate", 4, 1, 64);
        s.truth.geometry = f.choice("geometry", {"grid", "triangles"}, "grid") == "triangles"
                               ? TruthGeometry::Triangles
                               : TruthGeometry::Grid;
        s.truth.uncertainty = f.boolean("uncertainty", true);
        s.truth.memoryMb = f.integer("memory_mb", 1536, 1, 1 << 20);
        f.finish();
    }
    if (const PlaneBase* plane = s.plane()) {
        // Vertices of the plane's truth (the 2x-rate one when the uncertainty is asked for).
        double verts =
            PlaneLattice(*plane, s.height, s.truth.rate * (s.truth.uncertainty ? 2 : 1)).vertices();
        if (verts > double(1u << 31))
            throw InputError(s.file, "truth.rate", std::to_string(s.truth.rate),
                             "rate x map size x tiling asks for " + std::to_string(int64_t(verts)) +
                                 " truth vertices (more than 2^31); lower the rate or the tiling");
    }
}

}  // namespace

std::string toString(MeshTruth truth) { return truth == MeshTruth::Limit ? "limit" : "polygonal"; }

std::string toString(Projection projection) {
    return projection == Projection::Pinhole ? "pinhole" : "orthographic";
}

std::string toString(Framing framing) {
    return framing == Framing::Fill ? "fill" : framing == Framing::View ? "view" : "plane";
}

Scene parseScene(const Json& json, const std::string& file) {
    Scene s;
    s.file = file;
    s.json = json;
    JsonFields root(json, file, "");
    root.string("description", "");

    PendingImage pending;
    parseHeightmap(s, root, pending);
    s.height.address = root.choice("address", {"repeat", "clamp"}, "repeat") == "clamp"
                           ? Address::Clamp
                           : Address::Repeat;

    parseBase(s, root);
    if (root.has("displacement")) {
        JsonFields f(root.raw("displacement"), file, "displacement");
        s.displacement.scale = f.number("scale", 0.05, -1e3, 1e3);
        s.displacement.bias = f.number("bias", -s.displacement.scale / 2, -1e3, 1e3);
        f.finish();
    }
    parseCamera(s, root);
    parseLight(s, root);
    s.methods = parseMethods(root.raw("methods"), file, "methods");
    for (size_t i = 0; i < s.methods.size(); ++i)
        if (s.methods[i].lodGrad && !s.mipmaps)
            throw InputError(file, "methods[" + std::to_string(i) + "].lod", "grad",
                             "the height map has no mipmaps: add \"mipmaps\": true to "
                             "\"heightmap\"");
    parseTruth(s, root);
    if (root.has("sweep")) s.sweep = root.raw("sweep");
    if (root.has("fit")) s.fit = root.raw("fit");
    root.finish();
    if (!pending.path.empty()) {
        Address address = s.height.address;
        s.height =
            loadHeightImage(pending.path, pending.channel, file, "heightmap", pending.channelGiven);
        s.height.address = address;
    }
    if (s.mipmaps) addMipmaps(s.height);  // after the address mode: every level keeps it
    return s;
}

namespace {
Camera makeCameraUnjittered(const Scene& s, const ViewSpec& view);
}

Camera makeCamera(const Scene& s, const ViewSpec& view) {
    Camera cam = makeCameraUnjittered(s, view);
    cam.setJitter(view.camera.jitter, view.camera.jitterSeed);
    if (view.light) cam.setLight(viewFromAngles(view.light->theta, view.light->phi));
    return cam;
}

namespace {
Camera makeCameraUnjittered(const Scene& s, const ViewSpec& view) {
    const CameraSpec& c = view.camera;
    if (c.type == Projection::Pinhole)
        return Camera::pinhole(c.eye, c.target, c.up, c.fov, c.width, c.height);
    // docs/model.md §4: the camera looks along -V; image up is world +z made perpendicular to the
    // view direction, (-cos t cos p, -cos t sin p, sin t), which stays defined at theta = 0.
    Vec3d v = viewFromAngles(c.theta, c.phi);
    const double ct = cosDegrees(c.theta);
    Vec3d up(-ct * cosDegrees(c.phi), -ct * sinDegrees(c.phi), sinDegrees(c.theta));
    if (c.frame == Framing::View)
        return Camera::orthographic(-v, c.target, up, c.viewHeight, c.width, c.height);
    if (c.frame == Framing::Fill) {
        // The image's vertical extent on the plane is foreshortened by cos(theta); 1e-4
        // keeps the view non-degenerate at exactly 90 degrees.
        double height = c.fillSize * c.height / c.width * std::max(ct, 1e-4);
        return Camera::orthographic(-v, c.target, up, height, c.width, c.height);
    }
    // Fit the 8 corners of the relief slab; 2% margin so that the border stays visible.
    double l = s.worldPerUv(), sc = view.displacement.scale, b = view.displacement.bias;
    double zLo = std::min(l * b, l * (sc + b)), zHi = std::max(l * b, l * (sc + b));
    Vec3d boxLo, boxHi;  // the base with its relief
    reliefBox(s.base, zLo, zHi, boxLo, boxHi);
    Vec3d middle = (boxLo + boxHi) * 0.5;
    Camera probe = Camera::orthographic(-v, middle, up, 1.0, c.width, c.height);
    Vec2d lo(1e300), hi(-1e300);
    for (int k = 0; k < 8; ++k) {
        Vec3d corner(k & 1 ? boxHi.x : boxLo.x, k & 2 ? boxHi.y : boxLo.y,
                     k & 4 ? boxHi.z : boxLo.z);
        Vec3d q = probe.toCamera(corner);
        lo = glm::min(lo, Vec2d(q.x, q.y));
        hi = glm::max(hi, Vec2d(q.x, q.y));
    }
    Vec2d mid = (lo + hi) * 0.5;
    Vec3d target = middle + probe.right() * mid.x + probe.up() * mid.y;
    double aspect = double(c.width) / c.height;
    double height = std::max(hi.y - lo.y, (hi.x - lo.x) / aspect) * 1.02;
    return Camera::orthographic(-v, target, up, height, c.width, c.height);
}
}  // namespace

namespace {
// A block of the scene as the user wrote it (null for scenes built in code).
Json givenBlock(const Scene& s, const char* key) {
    return s.json.is_object() && s.json.contains(key) ? s.json.at(key) : Json();
}

// resolvedSceneJson's "base": the type and its settings as pgt understood them.
Json baseJson(const Scene& s) {
    return std::visit(Overloaded{[&](const PlaneBase& p) {
                                     return Json{{"type", "plane"},
                                                 {"size", p.size},
                                                 {"tiling", p.tiling},
                                                 {"center", {p.center.x, p.center.y, p.center.z}},
                                                 {"cull_back_faces", s.cullBackFaces},
                                                 {"infinite", p.infinite}};
                                 },
                                 [&](const MeshBase& m) {
                                     Json j{{"type", m.gltf ? "gltf" : "mesh"},
                                            {"source", m.source},
                                            {"sha1", m.cage->sourceSha1},
                                            {"given", givenBlock(s, "base")},
                                            {"scheme", toString(m.scheme)},
                                            {"refine", m.refine},
                                            {"truth_surface", toString(m.truthSurface)},
                                            {"world_per_uv", m.worldPerUv},
                                            {"cull_back_faces", s.cullBackFaces}};
                                     if (m.gltf) j["part"] = m.part, j["frames"] = m.frames;
                                     return j;
                                 }},
                      s.base);
}

// "drawn_mesh": a mesh's refined triangles and its frames' statistics; null for a plane.
Json drawnMeshJson(const BaseSurface& base) {
    return std::visit(
        Overloaded{[](const PlaneBase&) { return Json(nullptr); },
                   [](const MeshBase& m) {
                       const RefinedMesh& d = *m.drawn;
                       return Json{{"vertices", d.mesh.vertices.size()},
                                   {"triangles", d.mesh.indices.size() / 3},
                                   {"degenerate_uv_triangles", d.frames.degenerateUvTriangles},
                                   {"fallback_tangents", d.frames.fallbackTangents},
                                   {"mirrored_vertices", d.frames.mirroredVertices}};
                   }},
        base);
}

Json cameraJson(const CameraSpec& c) {
    Json camera;
    if (c.type == Projection::Pinhole) {
        camera = {{"type", "pinhole"},
                  {"eye", {c.eye.x, c.eye.y, c.eye.z}},
                  {"target", {c.target.x, c.target.y, c.target.z}},
                  {"up", {c.up.x, c.up.y, c.up.z}},
                  {"fov", c.fov}};
    } else {
        camera = {{"type", "orthographic"},
                  {"theta", c.theta},
                  {"phi", c.phi},
                  {"frame", toString(c.frame)},
                  {"target", {c.target.x, c.target.y, c.target.z}}};
        if (c.frame == Framing::Fill) camera["fill_size"] = c.fillSize;
        if (c.frame == Framing::View) camera["view_height"] = c.viewHeight;
    }
    camera["resolution"] = {c.width, c.height};
    camera["samples"] = c.jitter ? "jittered" : "centre";
    if (c.jitter) camera["seed"] = c.jitterSeed;
    return camera;
}
}  // namespace

Json resolvedSceneJson(const Scene& s, const ViewSpec& view) {
    Json methods = Json::array();
    for (const auto& m : s.methods) methods.push_back(toJson(m));
    Json out = {
        // The block as written (every generator parameter) and the file's content hash.
        {"heightmap",
         {{"source", s.heightSource},
          {"size", {s.height.width, s.height.height}},
          {"given", givenBlock(s, "heightmap")},
          {"sha1", s.heightSha1}}},
        {"address", toString(s.height.address)},
        {"base", baseJson(s)},
        {"drawn_mesh", drawnMeshJson(s.base)},
        {"displacement", {{"scale", view.displacement.scale}, {"bias", view.displacement.bias}}},
        {"camera", cameraJson(view.camera)},
        {"methods", methods},
        {"truth",
         {{"rate", s.truth.rate},
          {"geometry", s.truth.geometry == TruthGeometry::Grid ? "grid" : "triangles"},
          {"uncertainty", s.truth.uncertainty},
          {"memory_mb", s.truth.memoryMb}}},
    };
    // Only with a light: a study without one keeps the identity it had before lights.
    if (view.light) out["light"] = {{"theta", view.light->theta}, {"phi", view.light->phi}};
    return out;
}

const char* baseType(const BaseSurface& base) {
    return std::visit(Overloaded{[](const PlaneBase&) { return "plane"; },
                                 [](const MeshBase&) { return "mesh"; }},
                      base);
}

double worldPerUv(const BaseSurface& base) {
    return std::visit(Overloaded{[](const PlaneBase& p) { return p.worldPerUv(); },
                                 [](const MeshBase& m) { return m.worldPerUv; }},
                      base);
}

UvExtent uvExtentOf(const BaseSurface& base) {
    return std::visit(Overloaded{[](const PlaneBase& p) { return UvExtent(p.tiling); },
                                 [](const MeshBase& m) {
                                     UvExtent box{Vec2d(HUGE_VAL), Vec2d(-HUGE_VAL)};
                                     for (const Vec2d& uv : m.cage->uvs)
                                         box.lo = glm::min(box.lo, uv),
                                         box.hi = glm::max(box.hi, uv);
                                     return box;
                                 }},
                      base);
}

bool framesCanDiffer(const BaseSurface& base) {
    // A plane's per-vertex frame is its exact frame; a mesh's is an average over triangles.
    return std::visit(
        Overloaded{[](const PlaneBase&) { return false; }, [](const MeshBase&) { return true; }},
        base);
}

void reliefBox(const BaseSurface& base, double zLo, double zHi, Vec3d& lo, Vec3d& hi) {
    std::visit(Overloaded{[&](const PlaneBase& p) {
                              // The tile with its relief slab along +z.
                              lo = p.center + Vec3d(-0.5 * p.size, -0.5 * p.size, zLo);
                              hi = p.center + Vec3d(0.5 * p.size, 0.5 * p.size, zHi);
                          },
                          [&](const MeshBase& m) {
                              // The drawn mesh grown by the relief in every direction.
                              lo = Vec3d(1e300), hi = Vec3d(-1e300);
                              for (const auto& vtx : m.drawn->mesh.vertices)
                                  lo = glm::min(lo, vtx.position), hi = glm::max(hi, vtx.position);
                              const double grow = std::max(std::fabs(zLo), std::fabs(zHi));
                              lo -= Vec3d(grow), hi += Vec3d(grow);
                          }},
               base);
}

}  // namespace pgt
