// Curved bases: cages, OBJ loading, OpenSubdiv refinement and Lengyel FGED 2 Listing 7.4 frames.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "frame/render.h"
#include "mesh/control_mesh.h"
#include "mesh/refine.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "test_util.h"

namespace pgt {
namespace {

double angleBetween(Vec3d a, Vec3d b) {  // atan2 form: accurate near 0 (acos is not)
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// On a cylinder the analytic frame is T = d/du = around (-sin a, cos a, 0), B = +z, N radial.
// The Catmull-Clark limit of a 32-gon tube is a cubic B-spline around, not a circle: its
// normal leaves the radial direction by up to 1.3e-4 rad (measured; 4.9e-4 with 16
// segments). Listing 7.4 averages the per-triangle dS/du (chord directions); at the seam
// each side sees only its own chords, half a segment angle off, but the chord error lies in
// the plane of n and the true tangent, so Gram-Schmidt against the exact limit normal
// (Eq. 7.38) removes it. Stated tolerance: 2e-4 rad everywhere, seam included.
TEST(Mesh, CylinderFramesMatchTheAnalyticFrame) {
    const int segments = 32, levels = 2;
    ControlMesh cage = makeCylinderCage(1.0, 2.0, segments, 1.0, 1.0);
    RefinedMesh r = refineToTriangles(cage, Scheme::Catmark, levels);
    EXPECT_EQ(r.frames.degenerateUvTriangles, 0);
    EXPECT_EQ(r.frames.fallbackTangents, 0);
    EXPECT_EQ(r.frames.mirroredVertices, 0);
    double inside = 0, seam = 0, normal = 0;
    int seamVertices = 0;
    for (const auto& v : r.mesh.vertices) {
        double a = std::atan2(v.position.y, v.position.x);
        Vec3d t(-std::sin(a), std::cos(a), 0), n(std::cos(a), std::sin(a), 0);
        double e = std::max(angleBetween(v.tangent, t), angleBetween(v.bitangent, Vec3d(0, 0, 1)));
        bool atSeam = v.uv.x < 1e-9 || v.uv.x > 1 - 1e-9;
        seamVertices += atSeam;
        (atSeam ? seam : inside) = std::max(atSeam ? seam : inside, e);
        normal = std::max(normal, angleBetween(v.normal, n));
    }
    EXPECT_LT(normal, 2e-4);
    EXPECT_LT(inside, 2e-4);
    EXPECT_LT(seam, 2e-4);
    EXPECT_EQ(seamVertices, 2 * 5);  // both sides of the seam, 5 rings after 2 levels
    RecordProperty("normal_error_rad", std::to_string(normal));
    RecordProperty("inside_frame_error_rad", std::to_string(inside));
    RecordProperty("seam_frame_error_rad", std::to_string(seam));
}

BaseMesh quad(bool mirrored) {
    BaseMesh m;
    const Vec2d uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const Vec3d p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int k = 0; k < 4; ++k) {
        BaseVertex v;
        v.position = p[k];
        v.uv = mirrored ? Vec2d(1 - uv[k].x, uv[k].y) : uv[k];
        v.normal = Vec3d(0, 0, 1);
        m.vertices.push_back(v);
    }
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

// A texture mirrored in u (u decreasing along +x) flips the frame's handedness: w = -1, and
// the bitangent still follows +v.
TEST(Mesh, MirroredUvsGetNegativeHandedness) {
    BaseMesh plain = quad(false), mirrored = quad(true);
    auto w0 = computeTangentFrames(plain, nullptr);
    TangentFrameStats st;
    auto w1 = computeTangentFrames(mirrored, &st);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(w0[i], 1.0f);
        EXPECT_EQ(w1[i], -1.0f);
        EXPECT_LT(angleBetween(mirrored.vertices[i].tangent, Vec3d(-1, 0, 0)), 1e-12);
        EXPECT_LT(angleBetween(mirrored.vertices[i].bitangent, Vec3d(0, 1, 0)), 1e-12);
    }
    EXPECT_EQ(st.mirroredVertices, 4);
}

// A triangle whose UVs collapse to a point would divide by zero in Listing 7.4: it is
// skipped and counted; a vertex that only it touches gets a fallback tangent, still finite.
TEST(Mesh, DegenerateUvTriangleIsCountedNotNaN) {
    BaseMesh m = quad(false);
    BaseVertex extra;
    extra.position = Vec3d(0.5, 1.5, 0);
    extra.uv = Vec2d(1, 1);
    extra.normal = Vec3d(0, 0, 1);
    m.vertices.push_back(extra);
    m.vertices[3].uv = Vec2d(1, 1);  // vertices 2, 3, 4 now share one UV
    m.indices = {0, 1, 2, 2, 4, 3};
    TangentFrameStats st;
    computeTangentFrames(m, &st);
    EXPECT_EQ(st.degenerateUvTriangles, 1);
    EXPECT_EQ(st.fallbackTangents, 2);  // vertices 3 and 4 touch only that triangle
    for (const auto& v : m.vertices) {
        EXPECT_TRUE(allFinite(v.tangent) && allFinite(v.bitangent)) << v.position.x;
        EXPECT_NEAR(glm::length(v.tangent), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(v.tangent, v.normal), 0.0, 1e-12);
    }
}

TEST(Mesh, CubeCageHasFlatFacesAndItsOwnUvSquarePerFace) {
    RefinedMesh r = refineToTriangles(makeCubeCage(2.0, 1.0), Scheme::Bilinear, 1);
    EXPECT_EQ(r.mesh.indices.size(), 6u * 4u * 2u * 3u);  // 4 quads per face after 1 level
    EXPECT_EQ(r.mesh.vertices.size(), 6u * 9u);           // per face 3 x 3, split at seams
    // Bilinear: smooth within a UV chart, so every vertex has its face's own normal.
    for (size_t k = 0; k < r.mesh.indices.size(); k += 3) {
        const auto& a = r.mesh.vertices[r.mesh.indices[k]];
        const auto& b = r.mesh.vertices[r.mesh.indices[k + 1]];
        const auto& c = r.mesh.vertices[r.mesh.indices[k + 2]];
        Vec3d n = glm::normalize(glm::cross(b.position - a.position, c.position - a.position));
        for (const auto* v : {&a, &b, &c}) {
            EXPECT_LT(angleBetween(v->normal, n), 1e-12);
            EXPECT_NEAR(glm::dot(glm::cross(v->tangent, v->bitangent), v->normal), 1.0, 1e-12);
        }
    }
    EXPECT_EQ(r.frames.mirroredVertices, 0);
    EXPECT_DOUBLE_EQ(worldPerUvFromAreas(makeCubeCage(2.0, 1.0)), 2.0);
}

TEST(Mesh, LoopNeedsTriangles) {
    EXPECT_THROW(refineToTriangles(makeCubeCage(1, 1), Scheme::Loop, 1), std::invalid_argument);
}

TEST(Mesh, ObjFilesLoadAndBadOnesNameTheFile) {
    auto dir = test::tempDir("obj");
    auto good = dir / "quad.obj", bad = dir / "novt.obj";
    std::ofstream(good) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                           "f 1/1 2/2 3/3 4/4\n";
    std::ofstream(bad) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n";
    ControlMesh m = loadObjMesh(good.string(), "scene.json", "base.file");
    EXPECT_EQ(m.numFaces(), 1);
    EXPECT_EQ(m.faceSizes[0], 4);
    EXPECT_DOUBLE_EQ(worldPerUvFromAreas(m), 1.0);
    try {
        loadObjMesh(bad.string(), "scene.json", "base.file");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("novt.obj"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("texture coordinates"), std::string::npos);
    }
    EXPECT_THROW(loadObjMesh((dir / "missing.obj").string(), "s", "base.file"), InputError);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// A flat Catmull-Clark grid is the plane itself (the limit of a regular affine grid, with
// edge-only boundary rules, is the grid): rendering it as a mesh must reproduce the plane's
// results. The two truths are tessellated differently (grid at rate 4 vs the drawn triangles
// split at rate 4), so their difference is bounded by the truth's own uncertainty.
TEST(MeshRender, FlatCatmarkGridReproducesThePlane) {
    auto dir = test::tempDir("flatgrid");
    {
        std::ofstream obj(dir / "grid.obj");
        const int n = 4;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                obj << "v " << double(i) / n - 0.5 << " " << double(j) / n - 0.5 << " 0\n";
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                obj << "vt " << double(i) / n << " " << double(j) / n << "\n";
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
                obj << "f " << a << "/" << a << " " << b << "/" << b << " " << c << "/" << c << " "
                    << d << "/" << d << "\n";
            }
    }
    std::string common = R"("heightmap": {"procedural": "sine", "size": [32, 32]},
        "displacement": {"scale": 0.05, "bias": -0.025},
        "camera": {"type": "orthographic", "theta": 50, "phi": 30, "resolution": [96, 96],
                   "frame": "plane"},
        "methods": ["parallax", "pom", "relief"], "truth": {"rate": 4, "uncertainty": false})";
    Scene plane =
        parseScene(nlohmann::json::parse("{" + common + R"(, "base": {"type": "plane"}})"),
                   (dir / "p.json").string());
    Scene mesh = parseScene(
        nlohmann::json::parse("{" + common +
                              R"(, "base": {"type": "mesh", "file": "grid.obj", "scheme": "catmark",
                                   "refine": 2, "world_per_uv": 1.0}})"),
        (dir / "m.json").string());
    // Same framing: the mesh's box is grown by the relief on every side, the plane's only in
    // z; give both the same explicit view.
    for (Scene* s : {&plane, &mesh}) {
        s->camera.frame = Framing::View;
        s->camera.viewHeight = 1.2;
        s->camera.target = Vec3d(0);
    }
    RenderResult a = renderFrame(plane, {.timingRepeats = 1}),
                 b = renderFrame(mesh, {.timingRepeats = 1});
    ASSERT_EQ(a.methods.size(), b.methods.size());
    EXPECT_EQ(a.raster.covered, b.raster.covered);
    for (size_t k = 0; k < a.methods.size(); ++k) {
        const auto& ea = a.methods[k].stats.error;
        const auto& eb = b.methods[k].stats.error;
        // 5e-3 texel: the two tessellations differ by the truth's own uncertainty (p99 about
        // 3e-3 texel at rate 4 on smooth maps, docs/outputs.md "How to read).
        EXPECT_NEAR(ea.mean, eb.mean, 5e-3 + 0.01 * ea.mean) << a.methods[k].config.label;
        EXPECT_NEAR(ea.p90, eb.p90, 5e-3 + 0.01 * ea.p90) << a.methods[k].config.label;
        // On a flat mesh the Listing 7.4 frame is exact.
        EXPECT_NEAR(b.methods[k].statsExactFrame.error.mean, eb.mean, 1e-6);
    }
    std::filesystem::remove_all(dir);
}

TEST(MeshRender, BundledMeshScenesRender) {
    for (const char* name : {"cube", "cylinder", "torus", "saddle_obj", "gltf_torus"}) {
        Scene s = loadScene(test::sceneDir() + "/" + name + ".json");
        s.camera.width = s.camera.height = 48;
        s.truth.rate = 1;
        RenderResult r = renderFrame(s, {.timingRepeats = 1});
        EXPECT_GT(r.raster.covered, 200) << name;
        // A mesh's truth has no plane lattice: its segment counts are 0, never read from the
        // plane grid a mesh does not have (an empty optional; aborts in the hardened build).
        EXPECT_EQ(r.truthBuild.segmentsU, 0) << name;
        EXPECT_EQ(r.truthBuild.segmentsV, 0) << name;
        for (const auto& m : r.methods) {
            EXPECT_GT(m.stats.error.count, 100) << name << " " << m.config.label;
            EXPECT_EQ(m.stats.nonfinite, 0) << name << " " << m.config.label;
            EXPECT_TRUE(m.haveExactFrame);
        }
    }
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// An 8 x 8 quad grid on z = 0 as an OBJ, its v bent by `bend` * sin(pi x) (0: an affine UV
// map); `collapse` >= 0 gives that column of quads zero UV width (column collapse + 1's u is
// column collapse's), so its triangles have no exact tangent frame.
void writeUvGrid(const std::filesystem::path& path, double bend, int collapse = -1) {
    std::ofstream obj(path);
    const int n = 8;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            obj << "v " << double(i) / n - 0.5 << " " << double(j) / n - 0.5 << " 0\n";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const int iu = collapse >= 0 && i == collapse + 1 ? collapse : i;
            obj << "vt " << double(iu) / n << " " << double(j) / n + bend * std::sin(kPi * i / n)
                << "\n";
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
            obj << "f " << a << "/" << a << " " << b << "/" << b << " " << c << "/" << c << " " << d
                << "/" << d << "\n";
        }
}

// The exact-frame split responds to the tangent frame: on a flat grid whose UVs are an
// affine map the Listing 7.4 frame is exact (share 0); bend the UV map (v shifted by a sine
// of x, so the direction of dS/du turns across the mesh) and neighbouring triangles disagree
// on dS/du: the per-vertex average differs from the triangle's own frame and the share is no
// longer 0. (Bending u by a sine of y would not do: dS/du keeps its direction and Listing
// 7.8 rebuilds B from n x t.)
TEST(MeshRender, FrameShareIsZeroForAffineUvsAndNotForBentOnes) {
    auto dir = test::tempDir("bentuv");
    auto writeGrid = [&](const std::string& name, double bend) { writeUvGrid(dir / name, bend); };
    writeGrid("affine.obj", 0.0);
    writeGrid("bent.obj", 0.3);
    auto share = [&](const std::string& obj) {
        std::string json = R"({"heightmap": {"procedural": "sine", "size": [32, 32]},
            "displacement": {"scale": 0.05, "bias": -0.025},
            "base": {"type": "mesh", "file": ")" +
                           obj + R"(", "scheme": "bilinear", "refine": 0},
            "camera": {"type": "orthographic", "theta": 60, "phi": 0, "resolution": [64, 64]},
            "methods": ["parallax"], "truth": {"rate": 2, "uncertainty": false}})";
        Scene s = parseScene(nlohmann::json::parse(json), (dir / "s.json").string());
        RenderResult r = renderFrame(s, {.timingRepeats = 1});
        // frame.exr's inputs: base.V (the frame the method got) against base.Vexact.
        const std::vector<std::string> names = frameChannelNames(s.methods);
        const size_t nc = names.size();
        auto at = [&](const std::string& n) {
            return size_t(std::find(names.begin(), names.end(), n) - names.begin());
        };
        std::vector<float> px(size_t(r.camera.width()) * r.camera.height() * nc);
        interleaveFrameBand(wholeFrameBand(r), px.data());
        double apart = 0;
        for (size_t k = 0; k < r.fragments.data.size(); ++k) {
            if (!r.fragments.data[k].covered) continue;
            for (const char* c : {"x", "y", "z"}) {
                const float v = px[k * nc + at(std::string("base.V.") + c)],
                            e = px[k * nc + at(std::string("base.Vexact.") + c)];
                apart = std::max(apart, double(std::fabs(v - e)));
            }
        }
        return std::pair(
            1.0 - r.methods[0].statsExactFrame.error.mean / r.methods[0].stats.error.mean, apart);
    };
    const auto [affineShare, affineApart] = share("affine.obj");
    const auto [bentShare, bentApart] = share("bent.obj");
    EXPECT_NEAR(affineShare, 0.0, 1e-9);
    EXPECT_GT(std::fabs(bentShare), 1e-3);
    // The two V channels agree where the frames do, and part where they do not.
    EXPECT_LT(affineApart, 1e-6);
    EXPECT_GT(bentApart, 1e-3);
    std::filesystem::remove_all(dir);
}

// Pixels whose triangle has zero UV area have no exact frame: frame.exr's base.Vexact is NaN
// there (not a copy of base.V), the exact pass leaves them out, and frame_share_of_mean
// compares the two frames over the same pixels only: the per-vertex frame's mean over the
// pixels with an exact frame, recomputed here from the kept per-pixel errors.
TEST(MeshRender, PixelsWithoutAnExactFrameAreMarkedAndLeftOut) {
    auto dir = test::tempDir("degenerateuv");
    writeUvGrid(dir / "grid.obj", 0.3, 3);
    const std::string json = R"({"heightmap": {"procedural": "sine", "size": [32, 32]},
        "displacement": {"scale": 0.05, "bias": -0.025},
        "base": {"type": "mesh", "file": "grid.obj", "scheme": "bilinear", "refine": 0},
        "camera": {"type": "orthographic", "theta": 60, "phi": 30, "resolution": [64, 64]},
        "methods": ["parallax"], "truth": {"rate": 2, "uncertainty": false}})";
    Scene s = parseScene(nlohmann::json::parse(json), (dir / "s.json").string());
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    const MethodFrame& m = r.methods[0];
    ASSERT_TRUE(m.haveExactFrame);
    EXPECT_GT(r.raster.noExactFrame, 100);
    const std::vector<std::string> names = frameChannelNames(s.methods);
    const size_t nc = names.size();
    const size_t vx =
        size_t(std::find(names.begin(), names.end(), "base.Vexact.x") - names.begin());
    std::vector<float> px(size_t(r.camera.width()) * r.camera.height() * nc);
    interleaveFrameBand(wholeFrameBand(r), px.data());
    int64_t without = 0, with = 0;
    double sum = 0;
    for (size_t k = 0; k < r.fragments.data.size(); ++k) {
        const Fragment& f = r.fragments.data[k];
        if (!f.covered) continue;
        if (!f.exactFrame) {
            ++without;
            EXPECT_TRUE(std::isnan(px[k * nc + vx])) << k;
        } else if (std::isfinite(m.errTexels.data[k])) {
            ++with, sum += m.errTexels.data[k];
        }
    }
    EXPECT_EQ(without, r.raster.noExactFrame);
    EXPECT_EQ(m.statsExactFrame.error.count, with);
    EXPECT_LT(m.statsExactFrame.error.count, m.stats.error.count);
    EXPECT_NEAR(m.meanWhereExactFrame, sum / double(with), 1e-9 * sum / double(with));
    EXPECT_NEAR(frameShareOfMean(m), 1.0 - m.statsExactFrame.error.mean / (sum / double(with)),
                1e-9);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt

#include "truth/truth.h"

namespace pgt {
namespace {

// Limit truth: a Catmull-Clark torus (16 x 8 quads, UV seams where u and v wrap) tessellated
// face by face with Bfr. Corners and edge points are shared between faces except across the
// seams, so the vertex count is exactly: 17 x 9 UV corners + (128 + 16) u-edges x (ru - 1) +
// (128 + 8) v-edges x (rv - 1) + 128 faces x (ru - 1)(rv - 1) interior points, with
// ru = 32 texels / 16 = 2 and rv = 32 / 8 = 4 at rate 1.
TEST(LimitTruth, TorusSharesEveryPointOffTheSeams) {
    Texture t = test::smoothTexture(32, 32);
    ControlMesh cage = makeTorusCage(0.5, 0.2, 16, 8, 1.0, 1.0);
    auto tess = tessellateLimitSurface(t, cage, Scheme::Catmark, 1.0, 1);
    const int ru = 2, rv = 4;
    size_t want = 17 * 9 + 144 * (ru - 1) + 136 * (rv - 1) + 128 * (ru - 1) * (rv - 1);
    EXPECT_EQ(tess->sheet.position.size(), want);
    for (size_t k = 0; k < tess->sheet.normal.size(); ++k)
        ASSERT_NEAR(glm::length(Vec3d(tess->sheet.normal[k])), 1.0, 1e-6) << k;
}

// docs/model.md §5 on a curved surface: the limit cube's truth converges as the rate doubles.
TEST(LimitTruth, CubeConvergesWhenRateDoubles) {
    std::string json = R"({"heightmap": {"procedural": "sine", "size": [32, 32]},
        "base": {"type": "mesh", "cage": "cube", "scheme": "catmark", "refine": 3,
                 "truth_surface": "limit"},
        "displacement": {"scale": 0.04, "bias": -0.02},
        "camera": {"type": "orthographic", "theta": 50, "phi": 30, "resolution": [96, 96]},
        "methods": ["parallax"], "truth": {"rate": 1}})";
    Scene s = parseScene(nlohmann::json::parse(json), "limit.json");
    Camera cam = makeCamera(s);
    auto frame = [&](int rate) {
        auto base = tessellateLimitSurface(s.height, *std::get<MeshBase>(s.base).cage,
                                           std::get<MeshBase>(s.base).scheme, s.worldPerUv(), rate);
        TruthSurface surface(base, s.displacement, TruthGeometry::Triangles, false);
        return surface.traceFrame(cam);
    };
    auto f1 = frame(1), f2 = frame(2), f4 = frame(4);
    TruthUncertainty a = compareTruthFrames(f1, f2, s.height, s.height.address);
    TruthUncertainty b = compareTruthFrames(f2, f4, s.height, s.height.address);
    EXPECT_GT(a.pixelsCompared, 2000);
    EXPECT_LT(b.p99Texels, a.p99Texels * 0.6) << a.p99Texels << " -> " << b.p99Texels;
    EXPECT_LT(b.p50Texels, a.p50Texels * 0.6) << a.p50Texels << " -> " << b.p50Texels;
}

}  // namespace
}  // namespace pgt

#include "study/sweep.h"

namespace pgt {
namespace {

// the deferred-renderer blog's problem: a texture mirrored across a seam. Listing 7.4 gives w = -1
// on the mirrored half; on the mirror line itself the two halves' tangents cancel (fallbacks
// counted), and the error map shows the seam: most of pom's error there is frame error.
TEST(MeshRender, MirroredStripShowsItsSeam) {
    Scene s = loadScene(test::sceneDir() + "/mirrored_obj.json");
    const auto& drawn = *std::get<MeshBase>(s.base).drawn;
    int right = 0, left = 0;
    for (size_t k = 0; k < drawn.mesh.vertices.size(); ++k) {
        double x = drawn.mesh.vertices[k].position.x;
        if (x > 0.01) {
            EXPECT_EQ(drawn.handedness[k], -1.0f) << "x " << x;
            ++right;
        }
        if (x < -0.01) {
            EXPECT_EQ(drawn.handedness[k], 1.0f) << "x " << x;
            ++left;
        }
    }
    EXPECT_EQ(right, 20);
    EXPECT_EQ(left, 20);
    EXPECT_GT(drawn.frames.fallbackTangents, 0);
    s.camera.width = s.camera.height = 128;
    s.truth.uncertainty = false;
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    const MethodFrame& pom = r.methods[2];
    ASSERT_EQ(pom.config.name, "pom");
    EXPECT_GT(1 - pom.statsExactFrame.error.mean / pom.stats.error.mean, 0.5);
}

// Loop subdivision on a triangle cage (an octahedron, one UV chart per face), both truths.
TEST(MeshRender, LoopSchemeOnATriangleCage) {
    auto dir = test::tempDir("octa");
    {
        std::ofstream obj(dir / "octa.obj");
        obj << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
               "vt 0 0\nvt 1 0\nvt 0.5 1\n";
        const int f[8][3] = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5},
                             {3, 1, 6}, {2, 3, 6}, {4, 2, 6}, {1, 4, 6}};
        for (const auto& t : f) obj << "f " << t[0] << "/1 " << t[1] << "/2 " << t[2] << "/3\n";
    }
    for (const char* truth : {"polygonal", "limit"}) {
        std::string json = std::string(R"({"heightmap": {"procedural": "noise", "size": [32, 32]},
            "base": {"type": "mesh", "file": "octa.obj", "scheme": "loop", "refine": 2,
                     "truth_surface": ")") +
                           truth + R"("},
            "displacement": {"scale": 0.03, "bias": -0.015},
            "camera": {"type": "orthographic", "theta": 40, "phi": 20, "resolution": [64, 64]},
            "methods": ["parallax", "pom"], "truth": {"rate": 1}})";
        Scene s = parseScene(nlohmann::json::parse(json), (dir / "s.json").string());
        RenderResult r = renderFrame(s, {.timingRepeats = 1});
        EXPECT_GT(r.raster.covered, 500) << truth;
        for (const auto& m : r.methods) {
            EXPECT_EQ(m.stats.nonfinite, 0) << truth;
            EXPECT_GT(m.stats.error.count, 500) << truth;
        }
    }
    std::filesystem::remove_all(dir);
}

// Done means `pgt sweep` works on every bundled mesh scene: two cases each, small.
TEST(MeshRender, BundledMeshScenesSweep) {
    for (const char* name : {"cube", "cylinder", "torus", "saddle_obj", "mirrored_obj"}) {
        Scene s = loadScene(test::sceneDir() + "/" + name + ".json");
        s.truth.rate = 1;
        Study st = parseStudy(s);
        st.width = st.height = 32;
        st.timing = {1, 64, 1};
        auto dir = test::tempDir(std::string("meshsweep_") + name);
        SweepOptions opt;
        opt.outDir = dir.string();
        opt.progress = false;
        opt.maxCases = 2;
        SweepSummary sum = runSweep(s, st, opt);
        EXPECT_EQ(sum.done, 2) << name;
        std::ifstream in(dir / "results.csv");
        int lines = 0;
        for (std::string l; std::getline(in, l);) {
            if (lines++ == 0) continue;
            EXPECT_EQ(l.find(",nan,nan\n"), std::string::npos) << name << ": " << l;
        }
        EXPECT_EQ(lines, 1 + 2 * int(st.configs.size())) << name;
        std::filesystem::remove_all(dir);
    }
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// discard_outside on a mesh discards against the mesh's own UV extent (the cylinder's
// [0, 2] x [0, 1] with tiling [2, 1]), not a plane's default [0, 1]^2: a pixel is dropped
// exactly when the same method without the discard lands outside that extent.
TEST(MeshRender, DiscardOutsideUsesTheMeshUvExtent) {
    Scene s = loadScene(test::sceneDir() + "/cylinder.json");
    s.camera.width = s.camera.height = 128;
    s.methods = parseMethods(
        nlohmann::json::parse(R"(["parallax", {"name": "parallax", "discard_outside": true}])"),
        s.file, "methods");
    EXPECT_EQ(s.uvExtent.lo, Vec2d(0, 0));
    EXPECT_EQ(s.uvExtent.hi, Vec2d(2, 1));
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    const MethodFrame &plain = r.methods[0], &discard = r.methods[1];
    int64_t kept = 0, dropped = 0, beyondU1 = 0;
    for (size_t k = 0; k < plain.pixels.size(); ++k) {
        const MethodPixel& p = plain.pixels.data[k];
        if (!p.covered) continue;
        bool inside = p.uv.x >= 0 && p.uv.x <= 2 && p.uv.y >= 0 && p.uv.y <= 1;
        EXPECT_EQ(discard.pixels.data[k].covered, inside)
            << "pixel " << k << " uv' " << p.uv.x << ", " << p.uv.y;
        (inside ? kept : dropped)++;
        beyondU1 += inside && p.uv.x > 1;
    }
    EXPECT_GT(beyondU1, 1000) << "the test needs pixels with 1 < u' <= 2 (kept " << kept << ")";
    EXPECT_LT(dropped, kept / 10) << "only the seam's overshoots leave the extent";
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// The exact frame on a sheared, unequally scaled quad (docs/model.md §2): positions
// (0,0) (2,0) (2.6,1) (0.6,1) over UV [0,1]^2, so dS/du = (2,0,0), dS/dv = (0.6,1,0) and
// l = sqrt(2) (world area 2 over UV area 1). Closed forms: V_exact is M^-1 V normalised for
// M = [dS/du dS/dv l N] (inverted here with glm, not with the rasteriser's Cramer's rule), and
// on a constant map `parallax` fed V_exact lands on the truth (its offset (s h + b) V.xy / V.z
// is then the ray's own), while the orthonormal per-vertex frame misses by far more.
TEST(MeshRender, ExactFrameIsTheUvSpaceRayOnAShearedQuad) {
    auto dir = test::tempDir("shearquad");
    {
        std::ofstream obj(dir / "quad.obj");
        obj << "v 0 0 0\nv 2 0 0\nv 2.6 1 0\nv 0.6 1 0\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    }
    const double theta = 50, phi = 30;
    std::string json = R"({"heightmap": {"procedural": "constant", "value": 0.6, "size": [32, 32]},
        "displacement": {"scale": 0.04, "bias": -0.02},
        "base": {"type": "mesh", "file": "quad.obj", "scheme": "bilinear", "refine": 0},
        "camera": {"type": "orthographic", "theta": 50, "phi": 30, "target": [1.3, 0.5, 0],
                   "view_height": 0.7, "resolution": [48, 48]},
        "methods": ["parallax"], "truth": {"rate": 2, "uncertainty": false}})";
    Scene s = parseScene(nlohmann::json::parse(json), (dir / "s.json").string());
    const double l = s.worldPerUv();
    EXPECT_NEAR(l, std::sqrt(2.0), 1e-6);  // from the float cage
    RenderResult r = renderFrame(s, {.timingRepeats = 1});
    // The orthographic V: theta from +z, phi from +x toward +y (model.md §4: the plane's T, B).
    const double t = theta * kPi / 180, p = phi * kPi / 180;
    const Vec3d view(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    const glm::dmat3 m(Vec3d(2, 0, 0), Vec3d(0.6, 1, 0), Vec3d(0, 0, l));
    const Vec3d want = glm::normalize(glm::inverse(m) * view);
    int checked = 0;
    for (const Fragment& f : r.fragments.data) {
        if (!f.covered) continue;
        ASSERT_TRUE(f.exactFrame);
        // 1e-6: the cage's positions are read as floats (0.6 is 0.6000000238).
        EXPECT_NEAR(glm::length(f.viewTangentExact - want), 0.0, 1e-6);
        ++checked;
    }
    EXPECT_GT(checked, 1000);
    const auto& mf = r.methods[0];
    // The truth's own uncertainty on a flat relief is far below 1e-3 texel.
    EXPECT_LT(mf.statsExactFrame.error.max, 1e-3);
    EXPECT_GT(mf.stats.error.mean, 0.05);
    EXPECT_GT(1.0 - mf.statsExactFrame.error.mean / mf.stats.error.mean, 0.98);
    std::printf("sheared quad: parallax %.4f texel, %.2e with the exact frame\n",
                mf.stats.error.mean, mf.statsExactFrame.error.mean);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt
