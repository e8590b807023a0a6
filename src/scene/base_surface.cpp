// The base surface's contract (scene/base_surface.h): its parse, JSON, drawn mesh and the
// questions every stage asks it, one std::visit each.
#include "scene/base_surface.h"

#include <filesystem>

#include "core/format.h"
#include "core/json_read.h"
#include "core/memory.h"
#include "core/overloaded.h"
#include "mesh/gltf_mesh.h"
#include "scene/scene.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

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
}  // namespace

void parseBaseSurface(Scene& s, JsonFields& root) {
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

BaseMesh drawnBaseMesh(const BaseSurface& base, const Camera& camera) {
    return std::visit(Overloaded{[&](const PlaneBase& p) {
                                     const int tiles =
                                         p.infinite ? tilesToCover(camera, p.center, p.size) : 0;
                                     return makePlaneMesh(p.center, p.size, p.tiling, tiles);
                                 },
                                 [](const MeshBase& m) { return m.drawn->mesh; }},
                      base);
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
