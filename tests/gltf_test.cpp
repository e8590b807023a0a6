// glTF 2.0 bases (docs/scenes.md "glTF assets"): conventions against the plane base pixel for
// pixel, the asset's handedness, MikkTSpace against Blender's exported tangents (an
// independent implementation, tests/data/gltf/make_assets.py), the same mesh as OBJ and
// glTF, real assets and the broken ones of Debian's assimp-testmodels.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/error.h"
#include "frame/render.h"
#include "mesh/gltf_mesh.h"
#include "test_util.h"
#include "truth/tessellation.h"

namespace pgt {
namespace {

namespace fs = std::filesystem;

struct GltfVertex {
    float p[3], n[3], uv[2], t[4];
};

// A one-primitive glTF with its buffer in `stem`.bin beside it (POSITION, NORMAL, TEXCOORD_0,
// TANGENT, uint16 indices) and `node` as the node's JSON.
void writeGltf(const fs::path& dir, const std::string& stem, const std::vector<GltfVertex>& v,
               const std::vector<uint16_t>& idx, const std::string& node = R"({"mesh": 0})",
               int indexBytes = 2) {
    const size_t nv = v.size(), vb = nv * 48, ib = idx.size() * size_t(indexBytes);
    std::ofstream bin(dir / (stem + ".bin"), std::ios::binary);
    for (int a = 0; a < 4; ++a)  // attribute a of every vertex, one block each
        for (const auto& x : v) {
            const float* src = a == 0 ? x.p : a == 1 ? x.n : a == 2 ? x.uv : x.t;
            bin.write(reinterpret_cast<const char*>(src), a == 2 ? 8 : a == 3 ? 16 : 12);
        }
    for (uint16_t i : idx) {  // little-endian, 1, 2 or 4 bytes
        const uint32_t wide = i;
        bin.write(reinterpret_cast<const char*>(&wide), indexBytes);
    }
    bin.close();
    const size_t off[5] = {0, nv * 12, nv * 24, nv * 32, vb};
    std::ofstream g(dir / (stem + ".gltf"));
    g << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
      "nodes": [)"
      << node << R"(],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2,
                  "TANGENT": 3}, "indices": 4}]}],
      "buffers": [{"uri": ")"
      << stem + ".bin"
      << R"(", "byteLength": )" << vb + ib << R"(}],
      "bufferViews": [)";
    const size_t len[5] = {nv * 12, nv * 12, nv * 8, nv * 16, ib};
    for (int k = 0; k < 5; ++k)
        g << (k ? "," : "") << R"({"buffer": 0, "byteOffset": )" << off[k] << R"(, "byteLength": )"
          << len[k] << "}";
    g << R"(], "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": )"
      << nv << R"(, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5126, "count": )"
      << nv << R"(, "type": "VEC3"},
      {"bufferView": 2, "componentType": 5126, "count": )"
      << nv << R"(, "type": "VEC2"},
      {"bufferView": 3, "componentType": 5126, "count": )"
      << nv << R"(, "type": "VEC4"},
      {"bufferView": 4, "componentType": )"
      << (indexBytes == 1   ? 5121
          : indexBytes == 2 ? 5123
                            : 5125)
      << R"(, "count": )" << idx.size() << R"(, "type": "SCALAR"}]})";
}

// pgt's unit plane (docs/model.md §2) as glTF stores it: pgt (x, y, z) is glTF (x, z, -y),
// pgt's v is 1 - glTF's v; facing glTF's +Y, tangent +X with handedness w.
void writePlane(const fs::path& dir, const std::string& stem, float w,
                const std::string& node = R"({"mesh": 0})", int indexBytes = 2) {
    std::vector<GltfVertex> v;
    for (int k = 0; k < 4; ++k) {
        const float x = (k & 1) ? 0.5f : -0.5f, y = (k & 2) ? 0.5f : -0.5f;
        v.push_back({{x, 0, -y}, {0, 1, 0}, {x + 0.5f, 1 - (y + 0.5f)}, {1, 0, 0, w}});
    }
    // Counter-clockwise seen from glTF's +Y (pgt's +Z).
    writeGltf(dir, stem, v, {0, 1, 3, 0, 3, 2}, node, indexBytes);
}

const std::string kCommon = R"("heightmap": {"procedural": "sine", "size": [32, 32]},
    "displacement": {"scale": 0.05, "bias": -0.025},
    "camera": {"type": "orthographic", "theta": 50, "phi": 30, "resolution": [64, 64]},
    "methods": ["parallax", "pom"], "truth": {"rate": 4, "uncertainty": false})";

Scene scene(const fs::path& dir, const std::string& base) {
    Scene s = parseScene(nlohmann::json::parse("{" + kCommon + R"(, "base": )" + base + "}"),
                         (dir / "s.json").string());
    s.camera.frame = Framing::View;  // the same framing for every base
    s.camera.viewHeight = 1.2;
    s.camera.target = Vec3d(0);
    return s;
}

// The message a scene with this base is refused with ("" when it loads).
std::string sceneError(const fs::path& dir, const std::string& base) {
    try {
        scene(dir, base);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Gltf, PlaneEqualsThePlaneBasePixelForPixel) {
    auto dir = test::tempDir("gltf_plane");
    writePlane(dir, "plane", 1);
    RenderResult a = renderFrame(scene(dir, R"({"type": "plane"})"), {.timingRepeats = 1});
    RenderResult b =
        renderFrame(scene(dir, R"({"type": "gltf", "file": "plane.gltf"})"), {.timingRepeats = 1});
    ASSERT_EQ(a.raster.covered, b.raster.covered);
    int64_t compared = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const Fragment &fa = a.fragments.at(x, y), &fb = b.fragments.at(x, y);
            ASSERT_EQ(fa.covered, fb.covered) << x << "," << y;
            if (!fa.covered) continue;
            ++compared;
            EXPECT_NEAR(fa.uv0.x, fb.uv0.x, 1e-9);
            EXPECT_NEAR(fa.uv0.y, fb.uv0.y, 1e-9);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(fa.viewTangent[c], fb.viewTangent[c], 1e-9);
            for (size_t m = 0; m < a.methods.size(); ++m) {
                const Vec2d ua = a.methods[m].pixels.at(x, y).uv,
                            ub = b.methods[m].pixels.at(x, y).uv;
                EXPECT_NEAR(ua.x, ub.x, 1e-6);
                EXPECT_NEAR(ua.y, ub.y, 1e-6);
            }
        }
    EXPECT_GT(compared, 1500);
    // The truths come from two tessellations (the plane's lattice, the mesh's triangles):
    // equal to the truth's own uncertainty.
    for (size_t m = 0; m < a.methods.size(); ++m)
        EXPECT_NEAR(a.methods[m].stats.error.mean, b.methods[m].stats.error.mean, 5e-3);
    fs::remove_all(dir);
}

TEST(Gltf, FlippedTangentWMirrorsTheOffsets) {
    auto dir = test::tempDir("gltf_w");
    writePlane(dir, "right", 1);
    writePlane(dir, "left", -1);
    RenderResult a =
        renderFrame(scene(dir, R"({"type": "gltf", "file": "right.gltf"})"), {.timingRepeats = 1});
    RenderResult b =
        renderFrame(scene(dir, R"({"type": "gltf", "file": "left.gltf"})"), {.timingRepeats = 1});
    int64_t compared = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const Fragment &fa = a.fragments.at(x, y), &fb = b.fragments.at(x, y);
            if (!fa.covered) continue;
            ++compared;
            EXPECT_NEAR(fb.viewTangent.x, fa.viewTangent.x, 1e-12);
            EXPECT_NEAR(fb.viewTangent.y, -fa.viewTangent.y, 1e-12);  // B = w cross(N, T)
            // parallax's offset depends on h(uv0) only: its v part mirrors exactly.
            const Vec2d da = a.methods[0].pixels.at(x, y).uv - fa.uv0;
            const Vec2d db = b.methods[0].pixels.at(x, y).uv - fb.uv0;
            EXPECT_NEAR(db.x, da.x, 1e-6);
            EXPECT_NEAR(db.y, -da.y, 1e-6);
        }
    EXPECT_GT(compared, 1500);
    fs::remove_all(dir);
}

std::string data(const std::string& rel) { return test::testDataDir() + "/gltf/" + rel; }

// Per triangle corner: pgt's MikkTSpace against the tangent Blender exported (the corners are
// in the file's order in both loads).
TEST(Gltf, MikkTSpaceMatchesBlendersTangents) {
    for (const char* file : {"sphere.gltf", "torus_mirrored.gltf", "cylinder.gltf"}) {
        const GltfMesh asset = loadGltfMesh(data(file), {}, MeshFrames::Asset, "t", "base.file");
        const GltfMesh mikk =
            loadGltfMesh(data(file), {}, MeshFrames::MikkTSpace, "t", "base.file");
        ASSERT_EQ(asset.framesUsed, "asset");
        ASSERT_EQ(mikk.framesUsed, "mikktspace");
        const auto& ia = asset.drawn.mesh.indices;
        const auto& im = mikk.drawn.mesh.indices;
        ASSERT_EQ(ia.size(), im.size()) << file;
        double worst = 0;
        int mirrored = 0;
        for (size_t c = 0; c < ia.size(); ++c) {
            const BaseVertex& va = asset.drawn.mesh.vertices[ia[c]];
            const BaseVertex& vm = mikk.drawn.mesh.vertices[im[c]];
            ASSERT_EQ(va.position, vm.position);
            ASSERT_EQ(va.handedness, vm.handedness) << file << " corner " << c;
            worst = std::max(worst, std::acos(std::min(1.0, glm::dot(va.tangent, vm.tangent))));
            mirrored += va.handedness < 0;
        }
        EXPECT_LE(worst, 1e-4) << file;  // radians
        if (std::string(file) == "torus_mirrored.gltf") {
            EXPECT_GT(mirrored, 100);
        }
        EXPECT_EQ(mikk.drawn.frames.fallbackTangents, 0);
    }
}

// The frame convention on every asset: T along dS/du and B = w cross(N, T) along dS/dv of each
// drawn triangle (pgt's u and v), and front faces counter-clockwise around N, on Blender's
// exports (node transform with non-uniform scale; mirrored UVs) and on planes under a
// mirroring node and with indices of every width.
TEST(Gltf, FramesFollowTheSurfacesUAndV) {
    auto dir = test::tempDir("gltf_frames");
    writePlane(dir, "mirror", 1, R"({"mesh": 0, "scale": [-1, 1, 1]})");
    writePlane(dir, "u8", 1, R"({"mesh": 0})", 1);
    writePlane(dir, "u32", 1, R"({"mesh": 0, "translation": [0, 2, 0]})", 4);
    for (const std::string& file : {data("sphere.gltf"), data("torus_mirrored.gltf"),
                                    data("cylinder.gltf"), (dir / "mirror.gltf").string(),
                                    (dir / "u8.gltf").string(), (dir / "u32.gltf").string()}) {
        for (const MeshFrames frames : {MeshFrames::Asset, MeshFrames::Pgt}) {
            const GltfMesh g = loadGltfMesh(file, {}, frames, "t", "base.file");
            const BaseMesh& m = g.drawn.mesh;
            int checked = 0, wrong = 0;
            for (size_t t = 0; t < m.indices.size(); t += 3) {
                const BaseVertex* v[3] = {&m.vertices[m.indices[t]], &m.vertices[m.indices[t + 1]],
                                          &m.vertices[m.indices[t + 2]]};
                const Vec3d e1 = v[1]->position - v[0]->position,
                            e2 = v[2]->position - v[0]->position;
                const Vec2d d1 = v[1]->uv - v[0]->uv, d2 = v[2]->uv - v[0]->uv;
                const double det = d1.x * d2.y - d2.x * d1.y;
                if (std::fabs(det) < 1e-9) continue;
                const Vec3d dSdu = (e1 * d2.y - e2 * d1.y) / det,
                            dSdv = (e2 * d1.x - e1 * d2.x) / det;
                const Vec3d face = glm::cross(e1, e2);
                for (const BaseVertex* c : v) {
                    ++checked;
                    wrong += glm::dot(c->tangent, dSdu) <= 0 || glm::dot(c->bitangent, dSdv) <= 0 ||
                             glm::dot(face, c->normal) <= 0;
                }
            }
            EXPECT_GT(checked, 5) << file;
            EXPECT_EQ(wrong, 0) << file << " frames " << toString(frames);
        }
    }
    const GltfMesh mirror =
        loadGltfMesh((dir / "mirror.gltf").string(), {}, MeshFrames::Asset, "t", "base.file");
    EXPECT_EQ(mirror.drawn.frames.mirroredVertices, 4);  // w = 1 under a mirroring node: -1
    const GltfMesh moved =
        loadGltfMesh((dir / "u32.gltf").string(), {}, MeshFrames::Asset, "t", "f");
    EXPECT_EQ(moved.drawn.mesh.vertices[0].position.z, 2.0);  // glTF's +Y is pgt's +Z
    fs::remove_all(dir);
}

// Blender wrote the sphere twice: glTF with its node transform, OBJ with the transformed
// positions (6 decimals). The same cage gives the same limit truth; the same triangles
// drawn give the same uv0.
struct PixelDiff {
    int64_t both = 0, differ = 0;
    double worst = 0, mean = 0;
};
template <class T, class Hit, class Uv>
PixelDiff comparePixels(const Image2D<T>& a, const Image2D<T>& b, Hit hit, Uv uv) {
    PixelDiff d;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const T &pa = a.at(x, y), &pb = b.at(x, y);
            if (hit(pa) != hit(pb)) ++d.differ;
            if (!hit(pa) || !hit(pb)) continue;
            ++d.both;
            const double e = glm::length(uv(pa) - uv(pb)) * 32;  // texels of the 32^2 map
            d.worst = std::max(d.worst, e);
            d.mean += e;
        }
    d.mean /= double(std::max<int64_t>(1, d.both));
    return d;
}

TEST(Gltf, SameMeshAsObjAndGltfGivesTheSameTruth) {
    const std::string dir = test::testDataDir() + "/gltf";
    const std::string limit =
        R"(, "truth_surface": "limit", "scheme": "loop", "world_per_uv": 1.5})";
    RenderResult a = renderFrame(scene(dir, R"({"type": "gltf", "file": "sphere.gltf")" + limit),
                                 {.timingRepeats = 1});
    RenderResult b =
        renderFrame(scene(dir, R"({"type": "mesh", "file": "sphere.obj", "refine": 0)" + limit),
                    {.timingRepeats = 1});
    const PixelDiff truth = comparePixels(
        a.truth, b.truth, [](const TruthSample& t) { return t.hit; },
        [](const TruthSample& t) { return t.uv; });
    EXPECT_GT(truth.both, 1000);
    EXPECT_LE(truth.differ, 8);    // silhouette pixels
    EXPECT_LT(truth.mean, 1e-4);   // texels
    EXPECT_LT(truth.worst, 0.05);  // where the eye ray grazes the relief
    // The drawn triangles: the OBJ unrefined and unmoved (bilinear) against the asset's.
    RenderResult c = renderFrame(
        scene(dir, R"({"type": "mesh", "file": "sphere.obj", "refine": 0, "scheme": "bilinear",
                       "world_per_uv": 1.5})"),
        {.timingRepeats = 1});
    const PixelDiff uv0 = comparePixels(
        a.fragments, c.fragments, [](const Fragment& f) { return f.covered; },
        [](const Fragment& f) { return f.uv0; });
    EXPECT_GT(uv0.both, 1000);
    EXPECT_LE(uv0.differ, 8);
    EXPECT_LT(uv0.worst, 1e-3);
}

// The unit plane again, its left half an 8 x 8 grid of small triangles, its right half fans of
// long thin ones from the two right corners to the grid's midline vertices: the fans' lattices
// are far finer than the short midline edges they share with the grid, where the polygonal
// truth snaps them (truth/tessellation.h). A crack there would show as a missed truth ray.
TEST(Gltf, MixedTriangleSizesKeepThePolygonalTruthWatertight) {
    auto dir = test::tempDir("gltf_fan");
    std::vector<GltfVertex> v;
    auto vertex = [&](float x, float y) {
        v.push_back({{x, 0, -y}, {0, 1, 0}, {x + 0.5f, 1 - (y + 0.5f)}, {1, 0, 0, 1}});
        return uint16_t(v.size() - 1);
    };
    std::vector<uint16_t> idx;
    uint16_t grid[9][9];
    for (int j = 0; j <= 8; ++j)
        for (int i = 0; i <= 8; ++i)
            grid[j][i] = vertex(-0.5f + float(i) / 16, -0.5f + float(j) / 8);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i)
            idx.insert(idx.end(), {grid[j][i], grid[j][i + 1], grid[j + 1][i + 1], grid[j][i],
                                   grid[j + 1][i + 1], grid[j + 1][i]});
    const uint16_t b = vertex(0.5f, -0.5f), c = vertex(0.5f, 0.5f);
    for (int j = 0; j < 4; ++j) idx.insert(idx.end(), {grid[j][8], b, grid[j + 1][8]});
    idx.insert(idx.end(), {grid[4][8], b, c});
    for (int j = 4; j < 8; ++j) idx.insert(idx.end(), {grid[j][8], c, grid[j + 1][8]});
    writeGltf(dir, "fan", v, idx);
    RenderResult a = renderFrame(scene(dir, R"({"type": "plane"})"), {.timingRepeats = 1});
    RenderResult m =
        renderFrame(scene(dir, R"({"type": "gltf", "file": "fan.gltf"})"), {.timingRepeats = 1});
    const PixelDiff truth = comparePixels(
        a.truth, m.truth, [](const TruthSample& t) { return t.hit; },
        [](const TruthSample& t) { return t.uv; });
    EXPECT_GT(truth.both, 1500);
    EXPECT_EQ(truth.differ, 0);
    EXPECT_LT(truth.mean, 5e-3);  // texels: two tessellations, within the truth's own uncertainty
    // The sheet itself: every edge used by one triangle only lies on the plane's border.
    const GltfMesh fan = loadGltfMesh((dir / "fan.gltf").string(), {}, MeshFrames::Asset, "s", "f");
    const auto sheet = tessellateDrawnMesh(test::smoothTexture(32, 32), fan.drawn.mesh, 1.0, 4);
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    const auto& tri = sheet->sheet.triangles;
    for (size_t k = 0; k < tri.size(); k += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t p = tri[k + size_t(e)], q = tri[k + size_t((e + 1) % 3)];
            ++uses[{std::min(p, q), std::max(p, q)}];
        }
    int inner = 0;
    for (const auto& [edge, count] : uses) {
        const Vec2d mid = (sheet->uvAt(edge.first) + sheet->uvAt(edge.second)) * 0.5;
        const bool border = std::min({mid.x, mid.y, 1 - mid.x, 1 - mid.y}) < 1e-9;
        inner += count == 1 && !border;
    }
    EXPECT_EQ(inner, 0) << "edges of one triangle inside the plane: a crack";
    fs::remove_all(dir);
}

// Debian's assimp-testmodels: real assets load (BoxTextured three ways: .gltf, .glb and
// embedded; TEXCOORD_1 of another), broken ones are one line naming what is wrong.
const std::string kModels = "/usr/share/assimp/models/glTF2/";

std::string loadError(const std::string& file, const std::string& extra = "") {
    try {
        loadGltfMesh(file, {}, MeshFrames::Asset, "scene.json", "base.file");
        (void)extra;
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(GltfAssets, RealAssetsLoad) {
    if (!fs::exists(kModels)) {
        GTEST_SKIP() << "assimp-testmodels is not installed";
    }
    size_t triangles = 0;
    for (const char* f :
         {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
          "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
        const GltfMesh m = loadGltfMesh(kModels + f, {}, MeshFrames::Asset, "s", "base.file");
        EXPECT_EQ(m.framesUsed, "mikktspace") << f;  // BoxTextured has no TANGENT
        if (triangles) {
            EXPECT_EQ(m.drawn.mesh.indices.size() / 3, triangles) << f;
        }
        triangles = m.drawn.mesh.indices.size() / 3;
        EXPECT_EQ(m.drawn.frames.fallbackTangents, 0);
    }
    EXPECT_EQ(triangles, 12u);
    GltfSelection second;
    second.uvSet = 1;
    const GltfMesh t = loadGltfMesh(kModels + "issue_3269/texcoord_crash.gltf", second,
                                    MeshFrames::Asset, "s", "base.file");
    EXPECT_GT(t.drawn.mesh.indices.size(), 0u);
}

TEST(GltfAssets, BrokenAssetsNameWhatIsWrong) {
    if (!fs::exists(kModels)) {
        GTEST_SKIP() << "assimp-testmodels is not installed";
    }
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"IndexOutOfRange/IndexOutOfRange.gltf",
         "accessor 0 (indices) element 0 is index 255; the primitive has 24 vertices"},
        {"IndexOutOfRange/AllIndicesOutOfRange.gltf",
         "is index 65535; the primitive has 24 vertices"},
        {"BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
         "accessor 1 (NORMAL) element 0 has length 0"},
        {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
         "accessor 2 (POSITION) element 0 is not finite (-inf)"},
        {"SchemaFailures/sceneWrongType.gltf", "File not found : BoxTextured0.bin"},
        {"MissingBin/BoxTextured.gltf", "File not found : BoxTextured0.bin"},
        {"RecursiveNodes/RecursiveNodes.gltf", "is its own ancestor (a cycle in \"children\")"},
        {"TestNoRootNode/NoScene.gltf", "the file has no mesh"},
        {"TestNoRootNode/SceneWithoutNodes.gltf", "the file has no mesh"},
        {"IncorrectVertexArrays/Cube.gltf", "the primitive has no TEXCOORD_0"},
        {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "the primitive has no TEXCOORD_0"},
        {"draco/2CylinderEngine.gltf",
         "the asset requires KHR_draco_mesh_compression; pgt reads uncompressed buffers"},
        {"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf",
         "has mode 0; pgt reads triangles (mode 4)"},
    };
    for (const auto& [file, expected] : cases) {
        const std::string message = loadError(kModels + file);
        EXPECT_NE(message.find(expected), std::string::npos) << file << ": " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.rfind("scene.json: base.file = " + kModels + file + ": ", 0), 0u)
            << message;
    }
    // A primitive by mesh name: the truncated one of IncorrectVertexArrays.
    GltfSelection truncated;
    truncated.meshName = "TruncatedCube";
    try {
        loadGltfMesh(kModels + "IncorrectVertexArrays/Cube.gltf", truncated, MeshFrames::Asset, "s",
                     "f");
        ADD_FAILURE() << "TruncatedCube loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "35 vertices and no indices, not a whole number of triangles"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfAssets, UriCannotLeaveTheAssetsFolder) {
    auto dir = test::tempDir("gltf_uri");
    fs::create_directories(dir / "asset");
    writePlane(dir, "outside", 1);  // outside.bin beside the folder
    writePlane(dir / "asset", "plane", 1);
    // A uri climbing out with .. is refused by name, an absolute one before anything is read.
    for (const auto& [uri, expected] : std::vector<std::pair<std::string, std::string>>{
             {"../outside.bin", "a uri leaves the asset's folder: ../outside.bin"},
             {(dir / "outside.bin").string(), "is not a path relative to the asset"},
             {std::string(5000, 'a') + ".bin", "File not found"}}) {  // longer than a path may be
        // The same plane whose buffer uri points out of its folder.
        std::ifstream in(dir / "asset" / "plane.gltf");
        std::string text((std::istreambuf_iterator<char>(in)), {});
        const size_t at = text.find("plane.bin");
        text.replace(at, 9, uri);
        std::ofstream(dir / "asset" / "escape.gltf") << text;
        const std::string message = loadError((dir / "asset" / "escape.gltf").string());
        EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
    // A path the user wrote may go anywhere: the scene names ../asset/plane.gltf.
    fs::create_directories(dir / "scenes");
    EXPECT_NO_THROW(scene(dir / "scenes", R"({"type": "gltf", "file": "../asset/plane.gltf"})"));
    fs::remove_all(dir);
}

// What would give wrong numbers silently is refused: a TANGENT along its NORMAL (no tangent
// plane, every V NaN) and a truth too large for memory (a floor tiled 1,000 times at 4
// samples per texel of a 32^2 map).
TEST(GltfAssets, SilentMistakesAreRefused) {
    auto dir = test::tempDir("gltf_silent");
    std::vector<GltfVertex> v;
    for (int k = 0; k < 4; ++k) {
        const float x = (k & 1) ? 0.5f : -0.5f, y = (k & 2) ? 0.5f : -0.5f;
        v.push_back({{x, 0, -y}, {0, 1, 0}, {x + 0.5f, 1 - (y + 0.5f)}, {0, 1, 0, 1}});
    }
    writeGltf(dir, "along_n", v, {0, 1, 3, 0, 3, 2});
    for (auto& x : v) x.t[0] = 1, x.t[1] = 0, x.uv[0] *= 1000, x.uv[1] *= 1000;
    writeGltf(dir, "tiled", v, {0, 1, 3, 0, 3, 2});
    auto error = [&](const std::string& base) { return sceneError(dir, base); };
    EXPECT_NE(error(R"({"type": "gltf", "file": "along_n.gltf"})")
                  .find("TANGENT element 0 is parallel to its NORMAL"),
              std::string::npos);
    // The truth's estimate is checked before any work (checkViewMemory), not by the parser.
    std::string tiled;
    try {
        const Scene s = scene(dir, R"({"type": "gltf", "file": "tiled.gltf"})");
        checkViewMemory(s, 8, 8, {.configs = &s.methods}, "camera.resolution");
    } catch (const InputError& e) {
        tiled = e.what();
    }
    EXPECT_NE(tiled.find("truth.rate = 4: the mesh's polygonal truth"), std::string::npos) << tiled;
    EXPECT_NE(tiled.find("more than the memory limit"), std::string::npos) << tiled;
    fs::remove_all(dir);
}

// Bad selections and values name the field.
TEST(GltfAssets, BadSelectionsAreClearErrors) {
    const std::string dir = test::testDataDir() + "/gltf";
    auto error = [&](const std::string& base) { return sceneError(dir, base); };
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "mesh": 3})").find("mesh 3 of 1"),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "mesh": "Cube"})")
                  .find("no mesh is named \"Cube\""),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "primitive": 1})")
                  .find("primitive 1 of mesh 0, which has 1"),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "uv": 1})").find("no TEXCOORD_1"),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "refine": 2})").find("refine"),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "nothing.gltf"})").find("nothing.gltf"),
              std::string::npos);
    EXPECT_NE(error(R"({"type": "gltf", "file": "sphere.gltf", "node": 4})").find("node 4 of 1"),
              std::string::npos);
    EXPECT_EQ(error(R"({"type": "gltf", "file": "sphere.gltf", "node": 0})"), "");
    EXPECT_NE(
        error(R"({"type": "gltf", "file": "sphere.gltf", "frames": "mikk"})").find("mikktspace"),
        std::string::npos);
}

}  // namespace
}  // namespace pgt
