// The engine's inputs (docs/methods.md "Engine inputs"): a shader given what a vertex stage
// passes (world position, normal, tangent, camera) rebuilds V itself, or builds its frame from
// screen derivatives, and V per vertex as jMonkeyEngine and Ogre compute it. Held to closed
// forms: on a plane the engine's V is pgt's per-pixel V; on a sheared affine quad the
// derivative frame is the UV Jacobian, so its UV-space direction is the exact frame's
// (docs/model.md §2); per-vertex V on a flat triangle is per-pixel V under any camera. Runs in
// Mesa llvmpipe like tests/gl_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "frame/render.h"
#include "methods/shader/glsl_spec.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "test_util.h"

namespace pgt {
namespace {

// V from the engine's inputs, in the interpolated frame made orthonormal (Listing 7.8), as an
// engine whose vertex stage passes world-space varyings builds it per pixel.
constexpr const char* kEngineV = R"(
    vec3 n = normalize(pgt_world_normal);
    vec3 t = normalize(pgt_world_tangent.xyz - n * dot(n, pgt_world_tangent.xyz));
    vec3 bt = cross(n, t) * pgt_world_tangent.w;
    vec3 e = normalize(pgt_camera_position - pgt_world_position);
    return ParallaxMapping(uv, vec3(dot(t, e), dot(bt, e), dot(n, e)));
)";

// The frame built from screen derivatives of the world position and uv (the construction
// three.js's perturbUv and Babylon's cotangent frame use, written here in pgt's words): the
// view vector's tangential part solved in the basis of the two position derivatives gives its
// UV direction; the height axis is N.e over l, world units to one UV unit.
constexpr const char* kDerivativeFrame = R"(
    vec3 sx = dFdx(pgt_world_position), sy = dFdy(pgt_world_position);
    vec2 tx = dFdx(uv), ty = dFdy(uv);
    vec3 n = normalize(pgt_world_normal);
    vec3 r1 = cross(sy, n), r2 = cross(n, sx);
    float det = dot(sx, r1);
    vec3 e = pgt_camera_position - pgt_world_position;
    vec2 screen = vec2(dot(r1, e), dot(r2, e)) / det;
    vec3 w = vec3(tx * screen.x + ty * screen.y, dot(n, e) / world_per_uv);
    return uv + 0.05 * w.xy / w.z;
)";

Scene sceneFrom(const std::filesystem::path& dir, const std::string& json) {
    return parseScene(nlohmann::json::parse(json), (dir / "s.json").string());
}

nlohmann::json parallaxEntry(const std::string& name) {
    return {{"name", name},
            {"glsl", "pgt:parallax.glsl"},
            {"sampler", "heightMap"},
            {"uniforms", {{"height_scale", "scale"}, {"height_bias", "bias"}}}};
}

// The largest distance in texels between two methods' uv' over the pixels both cover.
double largestGap(const RenderResult& r, size_t a, size_t b, int texels) {
    double worst = 0;
    const auto& pa = r.methods[a].pixels.data;
    const auto& pb = r.methods[b].pixels.data;
    for (size_t k = 0; k < pa.size(); ++k)
        if (pa[k].covered && pb[k].covered)
            worst = std::max(worst, glm::length(pa[k].uv - pb[k].uv) * texels);
    return worst;
}

// On a plane the engine's V (camera - position in the interpolated frame) is pgt's per-pixel
// V: pinhole and orthographic, GLSL and HLSL.
TEST(EngineInputs, OnAPlaneTheEnginesVIsThePerPixelV) {
    auto dir = test::tempDir("engine_plane");
    std::ofstream(dir / "engine_v.hlsl")
        << "Texture2D heightMap; SamplerState s_linear;\n"
           "float height_scale; float height_bias;\n"
           "float2 Parallax(float2 uv, float3 V) {\n"
           "    float h = heightMap.SampleLevel(s_linear, uv, 0).r * height_scale + "
           "height_bias;\n"
           "    return uv + h * V.xy / V.z;\n}\n";
    for (const char* camera :
         {R"({"type": "orthographic", "theta": 55, "phi": 35, "resolution": [64, 64]})",
          R"({"type": "pinhole", "eye": [0.3, -0.9, 0.7], "target": [0, 0, 0],
              "up": [0, 0, 1], "fov": 50, "resolution": [64, 64]})"}) {
        nlohmann::json methods = nlohmann::json::array();
        methods.push_back(parallaxEntry("pixel_v"));
        methods.back()["call"] = "ParallaxMapping(uv, V)";
        methods.push_back(parallaxEntry("engine_v"));
        methods.back()["inputs"] = "engine";
        methods.back()["body"] = kEngineV;
        methods.push_back({{"name", "engine_hlsl"},
                           {"hlsl", "engine_v.hlsl"},
                           {"sampler", "heightMap"},
                           {"inputs", "engine"},
                           {"uniforms", {{"height_scale", "scale"}, {"height_bias", "bias"}}},
                           {"body",
                            "float3 n = normalize(pgt_world_normal);\n"
                            "float3 t = normalize(pgt_world_tangent.xyz - n * "
                            "dot(n, pgt_world_tangent.xyz));\n"
                            "float3 bt = cross(n, t) * pgt_world_tangent.w;\n"
                            "float3 e = normalize(pgt_camera_position - "
                            "pgt_world_position);\n"
                            "return Parallax(uv, float3(dot(t, e), dot(bt, e), "
                            "dot(n, e)));"}});
        const Scene s = sceneFrom(dir, R"({"heightmap": {"procedural": "sine", "size": [64, 64]},
            "displacement": {"scale": 0.05, "bias": -0.025}, "base": {"type": "plane"},
            "camera": )" + std::string(camera) +
                                           R"(,
            "methods": )" + methods.dump() +
                                           R"(, "truth": {"rate": 1, "uncertainty": false}})");
        const RenderResult r = renderFrame(s, {.timingRepeats = 0});
        ASSERT_EQ(r.methods.size(), 3u);
        EXPECT_GT(r.methods[0].stats.error.count, 1000);
        // Float: V from float positions, 1e-7 of their size; the map's slope is a few texels
        // per texel, so uv' agrees to well under 1e-4 texel.
        const double glsl = largestGap(r, 0, 1, 64), hlsl = largestGap(r, 0, 2, 64);
        std::printf("engine V against per-pixel V: GLSL %.2e, HLSL %.2e texel\n", glsl, hlsl);
        EXPECT_LT(glsl, 1e-4);
        EXPECT_LT(hlsl, 1e-4);
    }
    std::filesystem::remove_all(dir);
}

// A sheared, unequally scaled quad (dS/du = (2,0,0), dS/dv = (0.6,1,0)): the frame built from
// dFdx/dFdy of the position and uv is the UV Jacobian, so the direction it gives is the exact
// frame's V (the true UV-space ray, model.md §2), helpers at the quad's border included; under
// "api" gl and d3d alike (both derivatives turn round together).
TEST(EngineInputs, DerivativeFrameOnAnAffineQuadIsTheUvJacobian) {
    auto dir = test::tempDir("engine_shear");
    {
        std::ofstream obj(dir / "quad.obj");
        obj << "v 0 0 0\nv 2 0 0\nv 2.6 1 0\nv 0.6 1 0\n"
               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    }
    for (const char* camera :
         {R"({"type": "orthographic", "theta": 50, "phi": 30, "target": [1.3, 0.5, 0],
              "view_height": 1.6, "resolution": [64, 64]})",
          R"({"type": "pinhole", "eye": [1.0, -1.2, 1.1], "target": [1.3, 0.5, 0],
              "up": [0, 0, 1], "fov": 40, "resolution": [64, 64]})"}) {
        std::ofstream(dir / "frame.glsl") << "uniform float world_per_uv;\n";
        nlohmann::json methods = nlohmann::json::array();
        for (const char* api : {"gl", "d3d"})
            methods.push_back({{"name", std::string("frame_") + api},
                               {"glsl", "frame.glsl"},
                               {"sampler", ""},
                               {"api", api},
                               {"inputs", "engine"},
                               {"uniforms", {{"world_per_uv", std::sqrt(2.0)}}},
                               {"body", kDerivativeFrame}});
        const Scene s = sceneFrom(dir, R"({"heightmap": {"procedural": "constant", "value": 0.5,
                "size": [32, 32]}, "displacement": {"scale": 0.04, "bias": -0.02},
            "base": {"type": "mesh", "file": "quad.obj", "scheme": "bilinear", "refine": 0,
                     "world_per_uv": 1.4142135623730951},
            "camera": )" + std::string(camera) +
                                           R"(,
            "methods": )" + methods.dump() +
                                           R"(, "truth": {"rate": 1, "uncertainty": false}})");
        const RenderResult r = renderFrame(s, {.timingRepeats = 0});
        double worst = 0;
        int n = 0;
        for (size_t k = 0; k < r.fragments.data.size(); ++k) {
            const Fragment& f = r.fragments.data[k];
            if (!f.covered) continue;
            const Vec3d v = f.viewTangentExact;
            const Vec2d want = f.uv0 + 0.05 * Vec2d(v.x, v.y) / v.z;
            for (const MethodFrame& m : r.methods)
                worst = std::max(worst, glm::length(m.pixels.data[k].uv - want));
            ++n;
        }
        std::printf("derivative frame against the exact frame: %d pixels, max %.2e UV\n", n, worst);
        EXPECT_GT(n, 1000);
        // Float positions (1e-7 of their size) over pixel steps of about 1e-2: 1e-5 of the
        // offset 0.05 |w.xy / w.z|.
        EXPECT_LT(worst, 2e-6);
    }
    std::filesystem::remove_all(dir);
}

// The largest distance between V per vertex and V per pixel over a kept frame's pixels
// (infinite where the frame kept no FragmentInputs).
double perVertexApart(const RenderResult& r) {
    if (r.fragmentInputs.data.size() != r.fragments.data.size()) return INFINITY;
    double apart = 0;
    for (size_t k = 0; k < r.fragments.data.size(); ++k)
        if (r.fragments.data[k].covered)
            apart = std::max(apart, glm::length(r.fragmentInputs.data[k].viewVertex -
                                                r.fragments.data[k].viewTangent));
    return apart;
}

// "V" on a preset entry against the preset's own gains _pv (or _pp) in its label, so that a
// preset stands beside itself in a list; a GLSL entry beside another of its name gains _pv
// as a built-in does (docs/methods.md).
TEST(EngineInputs, PerVertexLabels) {
    const std::vector<MethodConfig> m =
        parseMethods(nlohmann::json::array(
                         {{{"preset", "godot"}},
                          {{"preset", "godot"}, {"V", "per_vertex"}},
                          {{"preset", "jme"}, {"V", "per_pixel"}},
                          {{"preset", "jme"}, {"V", "per_vertex"}},
                          {{"preset", "godot"}, {"V", "per_vertex"}, {"label", "mine"}},
                          {{"name", "own"}, {"glsl", "pgt:layered.glsl"}},
                          {{"name", "own"}, {"glsl", "pgt:layered.glsl"}, {"V", "per_vertex"}}}),
                     "t", "methods");
    const std::vector<std::string> labels = {"godot", "godot_pv", "jme_pp", "jme",
                                             "mine",  "own",      "own_pv"};
    ASSERT_EQ(m.size(), labels.size());
    for (size_t i = 0; i < m.size(); ++i) EXPECT_EQ(m[i].label, labels[i]) << i;
}

// Per-vertex V: on a flat triangle the interpolated eye vector is the eye vector of the
// interpolated point, so "V": "per_vertex" equals per-pixel V under either camera (closed
// form); on the torus, whose frame turns from vertex to vertex, it does not.
TEST(EngineInputs, PerVertexVIsPerPixelVOnAPlaneOnly) {
    for (bool pinhole : {false, true}) {
        std::vector<MethodConfig> methods = {
            parseMethod(nlohmann::json{{"name", "parallax"}}, "t", "m"),
            parseMethod(nlohmann::json{{"name", "parallax"}, {"V", "per_vertex"}}, "t", "m")};
        assignLabels(methods, "t", "methods");
        EXPECT_EQ(methods[1].label, "parallax_pv");
        EXPECT_EQ(toJson(methods[1]).at("V"), "per_vertex");
        Scene s = test::planeScene(test::smoothTexture(32, 32), 0.05, -0.025, 60, 20, 48, methods);
        if (pinhole) {
            s.camera.type = Projection::Pinhole;
            s.camera.eye = Vec3d(0.4, -0.8, 0.6);
            s.camera.target = Vec3d(0);
            s.camera.up = Vec3d(0, 0, 1);
            s.camera.fov = 55;
        }
        s.truth.uncertainty = false;
        const RenderResult r = renderFrame(s, {.timingRepeats = 0});
        EXPECT_LT(perVertexApart(r), 1e-12) << pinhole;
        // frame.exr's base.Vvertex channels hold it (outputs.md).
        const std::vector<std::string> names = frameChannelNames(s.methods);
        ASSERT_EQ(names.size(), frameChannelCount(2, true));
        EXPECT_EQ(names.back(), "base.Vvertex.z");
        std::vector<float> px(r.fragments.data.size() * names.size());
        interleaveFrameBand(wholeFrameBand(r), px.data());
        for (size_t k = 0; k < r.fragments.data.size(); ++k) {
            if (!r.fragments.data[k].covered) continue;
            ASSERT_EQ(px[k * names.size() + names.size() - 1],
                      float(r.fragmentInputs.data[k].viewVertex.z));
        }
        EXPECT_NEAR(r.methods[1].stats.error.mean, r.methods[0].stats.error.mean, 1e-9);
    }
    Scene torus = loadScene(test::sceneDir() + "/torus.json");
    torus.camera.width = torus.camera.height = 48;
    torus.truth.rate = 1;
    torus.truth.uncertainty = false;
    torus.methods = {
        parseMethod(nlohmann::json{{"name", "parallax"}, {"V", "per_vertex"}}, "t", "m")};
    torus.methods[0].label = "parallax_pv";
    const double apart = perVertexApart(renderFrame(torus, {.timingRepeats = 0}));
    std::printf("torus: per-vertex V against per-pixel V, max %.3e\n", apart);
    EXPECT_GT(apart, 1e-3);
    EXPECT_TRUE(std::isfinite(apart));
}

// "inputs" and "V" are checked like every field, and "inputs" is part of the identity.
TEST(EngineInputs, FieldsAreChecked) {
    EXPECT_THROW(parseMethod(nlohmann::json{{"name", "pom"}, {"V", "per_face"}}, "t", "m"),
                 InputError);
    nlohmann::json e = parallaxEntry("p");
    e["inputs"] = "world";
    EXPECT_THROW(parseMethod(e, test::testDataDir() + "/scene.json", "m"), InputError);
    e["inputs"] = "engine";
    const MethodConfig cfg = parseMethod(e, test::testDataDir() + "/scene.json", "m");
    EXPECT_TRUE(cfg.shader()->engineInputs);
    EXPECT_EQ(toJson(cfg).at("inputs"), "engine");
}

}  // namespace
}  // namespace pgt
