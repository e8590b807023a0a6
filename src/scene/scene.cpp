// Scene file parsing and validation; the camera a scene describes.
#include "scene/scene.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/json_fields.h"
#include "core/json_read.h"
#include "heightfield/heightfield.h"
#include "heightfield/mipmaps.h"
#include "methods/config.h"

namespace pgt {

namespace fs = std::filesystem;

Scene loadScene(const std::string& path) { return parseScene(readJsonFile(path), path); }

Vec3d vec3(JsonFields& f, const std::string& key, double lo, double hi) {
    auto v = f.numbers(key, 3, lo, hi);
    return {v[0], v[1], v[2]};
}

Json givenBlock(const Scene& s, const char* key) {
    return s.json.is_object() && s.json.contains(key) ? s.json.at(key) : Json();
}

fs::path besideScene(const Scene& s, const std::string& rel) {
    return fs::path(rel).is_absolute() ? fs::path(rel) : fs::path(s.file).parent_path() / rel;
}

namespace {

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
        // Segments across the plane's lattice (the 2x-rate one's when the uncertainty is asked
        // for), each side an int. What a view builds is its window of it, which the memory
        // estimate counts (frame/view_memory.h).
        const PlaneLattice lattice(*plane, s.height, s.truth.rate * (s.truth.uncertainty ? 2 : 1));
        const double side = std::max(lattice.nu, lattice.nv);
        // A view framing the whole plane builds all of it: refused here, from the map's size
        // alone (an image's header), before anything is decoded.
        if (s.camera.frame == Framing::Plane && lattice.vertices() > double(1u << 31))
            throw InputError(s.file, "truth.rate", std::to_string(s.truth.rate),
                             "rate x map size x tiling asks for " +
                                 std::to_string(int64_t(lattice.vertices())) +
                                 " truth vertices (more than 2^31) for a view of the whole "
                                 "plane; lower the rate or the tiling, or frame less of it");
        if (side > double(1 << 30))
            throw InputError(s.file, "truth.rate", std::to_string(s.truth.rate),
                             "rate x map size x tiling asks for " + std::to_string(int64_t(side)) +
                                 " truth segments across the plane (more than 2^30); lower the "
                                 "rate or the tiling");
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

    parseBaseSurface(s, root);
    if (root.has("displacement")) {
        JsonFields f(root.raw("displacement"), file, "displacement");
        s.displacement.scale = f.number("scale", 0.05, -1e3, 1e3);
        s.displacement.bias = f.number("bias", -s.displacement.scale / 2, -1e3, 1e3);
        f.finish();
    }
    parseCamera(s, root);
    parseLight(s, root);
    s.methods = parseMethods(root.raw("methods"), file, "methods", s.worldPerUv());
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
    return cam;
}

std::optional<Vec3d> lightToward(const ViewSpec& view) {
    if (!view.light) return std::nullopt;
    return viewFromAngles(view.light->theta, view.light->phi);
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

}  // namespace pgt
