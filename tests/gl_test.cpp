// GLSL methods in a real OpenGL: every built-in method's GLSL twin under
// src/methods/builtin/ against the C++ method on the same float inputs, fetch counting, uniforms
// bound to the case's (s, b), and the user-facing errors (file and line of a compile error,
// a missing sampler or uniform). Runs on Mesa llvmpipe through EGL's surfaceless platform
// (CI installs it); a machine without any EGL fails these tests rather than skipping them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "compare/statistics.h"
#include "core/error.h"
#include "core/json_read.h"
#include "frame/render.h"
#include "gl_agree.h"
#include "heightfield/heightfield.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/registry.h"
#include "methods/shader/glsl_method.h"
#include "test_util.h"
#include "truth/builder.h"

namespace pgt {
namespace {

// The shipped shaders where pgt finds them (PGT_SHADER_DIR overrides the source tree).
std::string shaderDir() { return pgt::shaderDir(); }

using Inputs = test::Fragments;
using test::agree;
using test::Agreement;
Inputs randomInputs(int n, uint32_t seed) { return test::randomFragments(n, seed); }

MethodConfig glslMethod(const std::string& json) {
    return parseMethod(nlohmann::json::parse(json), shaderDir() + "/scene.json", "methods[0]");
}

TEST(Gl, ContextIsHeadlessOpenGl) {
    const GlInfo& gl = glContext();
    EXPECT_FALSE(gl.renderer.empty());
    EXPECT_NE(gl.version.find("4."), std::string::npos) << gl.version;
    std::printf("GL_RENDERER: %s; GL_VERSION: %s\n", gl.renderer.c_str(), gl.version.c_str());
}

// Every built-in against its twin, as the method table names it (glslTwin): a built-in
// without one fails here. The inputs are bit-identical; the differences come from the GL's
// arithmetic (its bilinear filter, fused multiply-adds, 1/x and normalize). The single-fetch
// methods and the Lengyel ones must agree within 1e-3 texel (or 1e-5 of the offset)
// everywhere; the marches may flip a layer where a float comparison ties (counted: at most 1%
// of fragments).
TEST(Gl, BuiltInShadersMatchTheCppMethods) {
    Texture bricks = test::bricks(128);
    const double s = 0.05, b = -0.025;
    Inputs in = randomInputs(20000, 5);
    for (const MethodKindInfo& kind : methodKinds()) {
        MethodConfig cpu = parseMethod(nlohmann::json{{"name", kind.name}}, "test", "m");
        ASSERT_TRUE(kind.twin.file) << kind.name << " has no GLSL twin in the method table";
        MethodConfig gl = glslTwin(cpu);
        // The twin made directly is the one its scene entry parses to (labelled by its name,
        // as assignLabels labels a GLSL entry).
        MethodConfig parsed = glslMethod(twinEntry(cpu).dump());
        parsed.label = parsed.name;
        EXPECT_EQ(toJson(gl), toJson(parsed)) << kind.name;
        Agreement a = agree(cpu, gl, bricks, s, b, in, 1e-3);
        std::printf(
            "%-15s fragments %lld, over the tolerance %lld, max within it %.2e texel, "
            "fetch count mismatches %lld\n",
            cpu.name.c_str(), (long long)a.n, (long long)a.over, a.maxTexels,
            (long long)a.fetchMismatch);
        if (kind.twin.marches) {
            EXPECT_LE(a.over, a.n / 100) << cpu.name;
            EXPECT_LE(a.fetchMismatch, a.n / 100) << cpu.name;
        } else if (cpu.name == "tangent_plane") {
            // Where dot(n, V) nearly vanishes the offset runs to hundreds or thousands of
            // texels and any rounding difference in the dot product is magnified without
            // bound (seen: 7 of 20,000, all with offsets of 240-5,700 texels): at most 0.1%.
            EXPECT_LE(a.over, a.n / 1000) << cpu.name;
            EXPECT_EQ(a.fetchMismatch, 0) << cpu.name;
        } else {
            EXPECT_EQ(a.over, 0) << cpu.name;
            EXPECT_EQ(a.fetchMismatch, 0) << cpu.name;
        }
    }
}

// {"builtins": "all", "twins": true} (scenes/glsl_twins.json) is every kind of the method table
// at its defaults, in the table's order, each followed by its GLSL twin "NAME_gl" as the table
// writes it (twinEntry); "twin": true does the same for one entry, "LABEL_gl" where it has a
// label; without "twins" the kinds alone.
TEST(Gl, BuiltinsAllListsEveryKindBesideItsTwin) {
    const auto kinds = methodKinds();
    const auto both = parseMethods(nlohmann::json::parse(R"([{"builtins": "all", "twins": true},
        {"name": "pom", "label": "pom_grad", "lod": "grad", "twin": true}])"),
                                   "t", "methods");
    ASSERT_EQ(both.size(), 2 * kinds.size() + 2);
    auto unlabelled = [](MethodConfig c) {  // parseMethod alone leaves labels to parseMethods
        c.label.clear();
        return toJson(c).dump();
    };
    for (size_t k = 0; k <= kinds.size(); ++k) {
        const MethodConfig& cpu = both[2 * k];
        const MethodConfig& gl = both[2 * k + 1];
        const std::string name = k < kinds.size() ? kinds[k].name : "pom";
        ASSERT_TRUE(cpu.builtin()) << k;
        EXPECT_EQ(cpu.name, name);
        EXPECT_TRUE(runsInGl(gl)) << cpu.label;
        // Named after the entry's own label, else its name (the list's two pom get the
        // labels pom_8_32 and pom_grad only after).
        MethodConfig entry = cpu;
        entry.label = k < kinds.size() ? name : "pom_grad";
        EXPECT_EQ(gl.label, entry.label + "_gl");
        const MethodConfig again = parseMethod(twinEntry(entry), "t", "m");
        EXPECT_EQ(unlabelled(gl), unlabelled(again)) << cpu.label;
        if (k < kinds.size()) {  // at the kind's defaults
            EXPECT_EQ(unlabelled(cpu), unlabelled(parseMethod(name, "t", "m"))) << name;
        }
    }
    EXPECT_TRUE(both.back().lodGrad);
    const auto alone =
        parseMethods(nlohmann::json::parse(R"([{"builtins": "all"}])"), "t", "methods");
    ASSERT_EQ(alone.size(), kinds.size());
    for (size_t k = 0; k < kinds.size(); ++k) EXPECT_EQ(alone[k].name, kinds[k].name);
    // The bundled scene is that list.
    const auto scene = parseMethods(readJsonFile(test::sceneDir() + "/glsl_twins.json")["methods"],
                                    "glsl_twins.json", "methods");
    ASSERT_EQ(scene.size(), both.size());
    for (size_t i = 0; i < both.size(); ++i)
        EXPECT_EQ(toJson(scene[i]).dump(), toJson(both[i]).dump()) << i;
}

// A twin asked where there is none, or asked wrongly, is refused naming the field.
TEST(Gl, TwinRequestsAreChecked) {
    auto error = [](const char* list) -> std::string {
        try {
            parseMethods(nlohmann::json::parse(list), "bad.json", "methods");
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(error(R"([{"preset": "godot", "twin": true}])").find("methods[0].twin"),
              std::string::npos);
    EXPECT_NE(error(R"([{"name": "pom", "twin": "yes"}])").find("expected true or false"),
              std::string::npos);
    EXPECT_NE(error(R"([{"builtins": "some"}])").find("methods[0].builtins"), std::string::npos);
    EXPECT_NE(error(R"([{"builtins": "all", "twin": true}])").find("twin"), std::string::npos);
    EXPECT_EQ(error(R"([{"name": "pom", "twin": false}])"), "");
}

// Head-on (V = +z) every shader returns uv0 (docs/model.md symmetry), through the GL path.
TEST(Gl, HeadOnShadersReturnUv0) {
    Texture t = test::smoothTexture(32, 32);
    Inputs in = randomInputs(500, 9);
    for (auto& v : in.view) v = Vec3f(0, 0, 1);
    MethodConfig pom =
        glslMethod(R"({"name":"g","glsl":"layered.glsl","function":"ParallaxOcclusion",
        "sampler":"heightMap","uniforms":{"height_scale":0.05,"height_bias":-0.05,"min_layers":8.0,
        "max_layers":32.0,"max_steps":0}})");
    GlslRun run = runGlsl(*pom.shader(), MapRefs{.height = &t}, 0.05, -0.05, in.uv0, in.view);
    for (size_t k = 0; k < in.uv0.size(); ++k)
        EXPECT_LT(glm::length(Vec2d(run.uv[k]) - Vec2d(in.uv0[k])), 2e-7) << k;
}

// Map textures belong to their owner (a study's method textures for one (s, b)): uploaded
// once per owner and map, deleted with it; a call without an owner frees its own at return.
TEST(Gl, MapUploadsAreOwnedAndFreed) {
    Texture t = test::smoothTexture(32, 32), other = test::smoothTexture(16, 16);
    Inputs in = randomInputs(200, 4);
    MethodConfig parallax =
        glslMethod(R"({"name":"g","glsl":"parallax.glsl","function":"ParallaxMapping",
        "sampler":"heightMap","uniforms":{"height_scale":0.05,"height_bias":-0.025}})");
    auto run = [&](const Texture& map, GlMapUploads* uploads) {
        return runGlsl(*parallax.shader(), MapRefs{.height = &map}, 0.05, -0.025, in.uv0, in.view,
                       0, uploads);
    };
    const GlslRun fresh = run(t, nullptr);
    const size_t before = GlMapUploads::liveTextures();
    {
        GlMapUploads a, b;
        EXPECT_EQ(run(t, &a).uv, fresh.uv);
        EXPECT_EQ(run(t, &a).uv, fresh.uv);  // the same texture, not a second upload
        EXPECT_EQ(a.size(), 1u);
        EXPECT_EQ(GlMapUploads::liveTextures(), before + 1);
        run(other, &a);
        run(t, &b);
        EXPECT_EQ(a.size(), 2u);
        EXPECT_EQ(b.size(), 1u);
        EXPECT_EQ(GlMapUploads::liveTextures(), before + 3);
    }
    EXPECT_EQ(GlMapUploads::liveTextures(), before);
    run(t, nullptr);
    EXPECT_EQ(GlMapUploads::liveTextures(), before);
}

std::string writeShader(const std::string& name, const std::string& text) {
    auto dir = test::tempDir("gl");
    std::string path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
}

// A compile error names the user's file and the line in it.
TEST(Gl, CompileErrorNamesFileAndLine) {
    std::string path = writeShader("broken.glsl",
                                   "uniform sampler2D depthMap;\n"
                                   "vec2 ParallaxMapping(vec2 uv, vec3 v) {\n"
                                   "    return uv + undefined_thing;\n"
                                   "}\n");
    MethodConfig cfg =
        parseMethod(nlohmann::json::parse(R"({"name":"mine","glsl":")" + path + R"("})"),
                    "scene.json", "methods[0]");
    Inputs in = randomInputs(4, 1);
    Texture t = test::smoothTexture(8, 8);
    try {
        runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
        FAIL() << "no error";
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find(path + ":3"), std::string::npos) << what;
        EXPECT_NE(what.find("undefined_thing"), std::string::npos) << what;
        EXPECT_EQ(what.find("pgt prelude"), std::string::npos) << what;  // all in the file
    }
}

TEST(Gl, MissingSamplerOrUniformIsNamed) {
    std::string path =
        writeShader("ok.glsl",
                    "uniform sampler2D depthMap;\nuniform float height_scale;\n"
                    "vec2 ParallaxMapping(vec2 uv, vec3 v) {\n"
                    "    return uv - v.xy * texture(depthMap, uv).r * height_scale;\n}\n");
    Inputs in = randomInputs(4, 1);
    Texture t = test::smoothTexture(8, 8);
    auto run = [&](const std::string& extra) {
        MethodConfig cfg = parseMethod(
            nlohmann::json::parse(R"({"name":"mine","glsl":")" + path + "\"" + extra + "}"),
            "scene.json", "methods[0]");
        return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
    };
    EXPECT_NO_THROW(run(R"(,"uniforms":{"height_scale":0.1})"));
    try {
        run(R"(,"sampler":"heightMap")");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "sampler");
        EXPECT_EQ(e.value(), "heightMap");
    }
    try {
        run(R"(,"uniforms":{"height_scal":0.1})");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "uniforms.height_scal");
    }
    // A depth-map shader: the sampler then holds d = 1 - h; offset by d * s: counted once.
    // Tolerance: a GPU's 8-bit filter weights (docs/methods.md "GPU filter precision") move a
    // sample by up to the map's range / 512, the offset by 0.1 |V.xy| times that; plus float
    // rounding.
    GlslRun r = run(R"(,"texture":"depth","uniforms":{"height_scale":0.1})");
    const auto [lo, hi] = std::minmax_element(t.texels.begin(), t.texels.end());
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        float d = 1.0f - sampleBilinear<float>(t, in.uv0[k]);
        Vec2f want = in.uv0[k] - Vec2f(in.view[k].x, in.view[k].y) * d * 0.1f;
        const double filter =
            0.1 * glm::length(Vec2d(in.view[k].x, in.view[k].y)) * (*hi - *lo) / 512;
        EXPECT_LT(glm::length(Vec2d(r.uv[k] - want)), 1e-5 + filter);
        EXPECT_EQ(r.fetches[k], 1u);
    }
}

// Code written in another dialect runs unchanged (docs/methods.md "GLSL dialects"): pgt's
// pom as WebGL 1 code (ES 1.00: texture2DLodEXT and its #extension line, precision
// statements, a constant-bound loop) and as WebGL 2 code (ES 3.00), held to the C++ built-in
// as the twins are, and to the shipped twin (the same arithmetic in the 4.50 wrapper).
TEST(Gl, EsDialectsRunUnchangedAndEqualTheBuiltIn) {
    Texture bricks = test::bricks(128);
    const double s = 0.05, b = -0.025;
    Inputs in = randomInputs(20000, 5);
    const MethodConfig cpu = parseMethod(nlohmann::json{{"name", "pom"}}, "test", "m");
    const MethodConfig twin = glslTwin(cpu);
    const GlslRun twinRun =
        runGlsl(*twin.shader(), MapRefs{.height = &bricks}, s, b, in.uv0, in.view);
    for (const auto& [file, version] :
         {std::pair<std::string, std::string>{"pom_es100.glsl", "100"},
          {"pom_es300.glsl", "300 es"}}) {
        const nlohmann::json entry = {{"name", "pom_es"},
                                      {"glsl", test::testDataDir() + "/glsl/" + file},
                                      {"function", "ParallaxOcclusionES"},
                                      {"sampler", "heightMap"},
                                      {"uniforms",
                                       {{"height_scale", "scale"},
                                        {"height_bias", "bias"},
                                        {"min_layers", 8.0},
                                        {"max_layers", 32.0}}}};
        const MethodConfig gl = glslMethod(entry.dump());
        EXPECT_EQ(gl.shader()->version, version) << file;
        const Agreement a = agree(cpu, gl, bricks, s, b, in, 1e-3);
        const GlslRun run =
            runGlsl(*gl.shader(), MapRefs{.height = &bricks}, s, b, in.uv0, in.view);
        double maxFromTwin = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k)
            maxFromTwin =
                std::max(maxFromTwin, uvErrorTexels(Vec2d(run.uv[k]), Vec2d(twinRun.uv[k]),
                                                    bricks.width, bricks.height, Address::Clamp));
        std::printf(
            "%s: fragments %lld, over 1e-3 texel from pom %lld, max within %.2e; fetch count "
            "mismatches %lld; largest difference from the shipped twin %.2e texel\n",
            file.c_str(), (long long)a.n, (long long)a.over, a.maxTexels,
            (long long)a.fetchMismatch, maxFromTwin);
        EXPECT_LE(a.over, a.n / 100) << file;
        EXPECT_LE(a.fetchMismatch, a.n / 100) << file;
        EXPECT_LE(maxFromTwin, 1e-3) << file;
    }
}

// The same code in GLSL and HLSL counts the same fetches: a fetch whose value is never used
// (counted in GLSL, where the counter keeps it; the HLSL compiler drops the fetch, but the
// count survives), a loop that stops at a height, an implicit-lod and an explicit-lod read, a
// Load and a subscript beside texelFetch (their values multiplied by 0), an unbalanced call
// in a comment (not counted); uv' alike too.
TEST(Gl, HlslAndGlslCountTheSameFetches) {
    const auto dir = test::tempDir("fetch_twins");
    std::ofstream(dir / "f.glsl")
        << "#version 450\nuniform sampler2D heightMap;\nuniform sampler2D other;\n"
           "vec2 F(vec2 uv, vec3 V) {\n"
           "    float unused = texture(heightMap, uv).r;\n    vec2 p = uv;\n"
           "    p.x += texelFetch(other, ivec2(3, 4), 0).r * 0.0;\n"
           "    p.y += texelFetch(other, ivec2(1, 2), 0).r * 0.0;\n"
           "    for (int i = 0; i < 8; ++i) {\n"
           "        if (textureLod(heightMap, p, 0.0).r < 0.5) break;\n"
           "        p += V.xy * 0.01;\n    }\n"
           "    return p;\n}\n";
    std::ofstream(dir / "f.hlsl")
        << "Texture2D heightMap;\nSamplerState heightSampler;\nTexture2D other;\n"
           "float2 F(float2 uv, float3 V) {\n"
           "    // heightMap.Sample(heightSampler, uv\n"
           "    float unused = heightMap.Sample(heightSampler, uv).r;\n    float2 p = uv;\n"
           "    p.x += other.Load(int3(3, 4, 0)).r * 0.0;\n"
           "    p.y += other[int2(1, 2)].r * 0.0;\n"
           "    for (int i = 0; i < 8; ++i) {\n"
           "        if (heightMap.SampleLevel(heightSampler, p, 0.0).r < 0.5) break;\n"
           "        p += V.xy * 0.01;\n    }\n"
           "    return p;\n}\n";
    const MethodConfig glsl = glslMethod(R"({"name": "g", "glsl": ")" + (dir / "f.glsl").string() +
                                         R"(", "function": "F", "sampler": "heightMap"})");
    const MethodConfig hlsl = glslMethod(R"({"name": "h", "hlsl": ")" + (dir / "f.hlsl").string() +
                                         R"(", "function": "F", "sampler": "heightMap"})");
    Inputs in = randomInputs(512, 7);
    Texture t = test::smoothTexture(16, 16);
    const GlslRun g = runGlsl(*glsl.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
    const GlslRun h = runGlsl(*hlsl.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
    std::set<uint32_t> counts;
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        EXPECT_EQ(g.fetches[k], h.fetches[k]) << k;
        EXPECT_LT(glm::length(Vec2d(g.uv[k] - h.uv[k])), 1e-6) << k;
        counts.insert(g.fetches[k]);
    }
    EXPECT_GT(counts.size(), 2u);  // the loop stops at different steps
    EXPECT_GE(*counts.begin(), 4u);
    std::filesystem::remove_all(dir);
}

// The dialect comes from the entry's "version" or the file's #version line; the legacy
// names (texture2D, ...) exist in 100, 110 and 120 only, so a 3.30 file may define its own
// texture2D; unknown versions and a desktop version beyond the GL's are refused by name.
TEST(Gl, DialectsAreNamedOrReadAndUnknownOnesRefused) {
    const std::string own = test::testDataDir() + "/glsl/own_texture2d.glsl";
    Inputs in = randomInputs(64, 3);
    Texture t = test::smoothTexture(8, 8);
    auto entry = [&](const std::string& path, const std::string& extra) {
        return glslMethod(R"({"name":"mine","glsl":")" + path +
                          R"(","uniforms":{"height_scale":0.1})" + extra + "}");
    };
    const MethodConfig desktop = entry(own, "");
    EXPECT_EQ(desktop.shader()->version, "330");
    const GlslRun r = runGlsl(*desktop.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        const float d = 1.0f - sampleBilinear<float>(t, in.uv0[k]);
        const Vec2f want = in.uv0[k] - Vec2f(in.view[k].x, in.view[k].y) * d * 0.1f;
        EXPECT_LT(glm::length(Vec2d(r.uv[k] - want)), 1e-4) << k;
        EXPECT_EQ(r.fetches[k], 1u);
    }
    // Named ES 1.00, its own texture2D meets the legacy name: a compile error in its file.
    const MethodConfig legacy = entry(own, R"(,"version":"100")");
    EXPECT_EQ(legacy.shader()->version, "100");
    try {
        runGlsl(*legacy.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(own + ":7"), std::string::npos) << e.what();
    }
    for (const std::string bad :
         {R"(,"version":"500")", R"(,"version":"330 es")", R"(,"version":true)"}) {
        try {
            entry(own, bad);
            FAIL() << bad;
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), "methods[0].version") << e.what();
        }
    }
    const std::string odd = writeShader("odd.glsl", "// a comment\n#version 999\n");
    try {
        entry(odd, "");
        FAIL() << "#version 999 accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "#version");
        EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    }
    const MethodConfig newer = entry(own, R"(,"version":"460")");
    if (glContext().glslVersion >= 460) {
        EXPECT_NO_THROW(runGlsl(*newer.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view));
    } else {
        try {
            runGlsl(*newer.shader(), MapRefs{.height = &t}, 0.1, 0, in.uv0, in.view);
            FAIL() << "460 accepted by a GL with GLSL " << glContext().glslVersion;
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), "version");
            EXPECT_NE(std::string(e.what()).find("compiles GLSL up to"), std::string::npos);
        }
    }
}

// The engine presets on a constant height h (depth d = 1 - h) have closed forms: Godot's
// offset without the division by V.z, uv0 - V.xy * 0.05 * d, for the plain and the deep
// variant (its occlusion step lands exactly on a flat depth); Bevy's occlusion divides by
// |V.z|: uv0 - V.xy * 0.1 * d / |V.z|; its relief refinement lands within half a layer / 2^5.
TEST(Gl, EnginePresetsHaveTheirClosedFormsOnFlatDepth) {
    const double h = 0.3, d = 1 - h;
    Texture t = test::makeTexture(16, 16, [&](int, int) { return h; });
    Inputs in = randomInputs(400, 13);
    auto preset = [&](const char* name) {
        MethodConfig cfg = parseMethod(nlohmann::json::parse(std::string(R"({"preset":")") + name +
                                                             R"(","amplitude":"shipped"})"),
                                       "scene.json", "methods[0]");
        EXPECT_EQ(cfg.preset, name);
        return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.025, in.uv0, in.view);
    };
    GlslRun godot = preset("godot"), deep = preset("godot_deep");
    GlslRun occlusion = preset("bevy_occlusion"), relief = preset("bevy_relief");
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        Vec2d uv0(in.uv0[k]);
        Vec3d v(in.view[k]);
        Vec2d g = uv0 - Vec2d(v.x, v.y) * 0.05 * d;
        EXPECT_LT(glm::length(Vec2d(godot.uv[k]) - g), 1e-6) << k;
        EXPECT_LT(glm::length(Vec2d(deep.uv[k]) - g), 2e-6) << k;
        EXPECT_EQ(godot.fetches[k], 1u);
        Vec2d b = uv0 - Vec2d(v.x, v.y) * 0.1 * d / std::fabs(v.z);
        EXPECT_LT(glm::length(Vec2d(occlusion.uv[k]) - b), 1e-5 * (1 + glm::length(b - uv0))) << k;
        double layers = 16 * (1 - std::fabs(v.z)) + std::fabs(v.z);
        double step = 0.1 / layers * glm::length(Vec2d(v.x, v.y)) / std::fabs(v.z);
        EXPECT_LT(glm::length(Vec2d(relief.uv[k]) - b), step / 32 + 1e-6) << k;
    }
}

// The source documents' own settings are the built-in methods with their (s, b).
TEST(Gl, DocumentPresetsAreTheBuiltInsAtTheirSettings) {
    auto preset = [](const char* name) {
        return parseMethod(nlohmann::json::parse(std::string(R"({"preset":")") + name +
                                                 R"(","amplitude":"shipped"})"),
                           "scene.json", "methods[0]");
    };
    MethodConfig welsh = preset("welsh");
    EXPECT_EQ(welsh.builtin()->kind, MethodKind::Parallax);
    EXPECT_EQ(welsh.scale, 0.04);
    EXPECT_EQ(welsh.bias, -0.02);
    MethodConfig blog = preset("deferred_blog");
    EXPECT_EQ(blog.builtin()->kind, MethodKind::Steep);
    EXPECT_EQ(blog.builtin()->as<LayerParameters>().maxLayers, 100);
    EXPECT_EQ(blog.builtin()->as<LayerParameters>().maxSteps, 100);
    EXPECT_EQ(blog.scale, 0.15);
    EXPECT_EQ(blog.label, "deferred_blog_shipped");
    MethodConfig lpom = preset("learnopengl_pom");
    EXPECT_EQ(lpom.builtin()->kind, MethodKind::Pom);
    EXPECT_EQ(lpom.scale, 0.1);
    EXPECT_EQ(lpom.bias, -0.1);
    EXPECT_THROW(preset("unreal"), InputError);
}

// Every pipeline draws a GLSL method band by band, each draw through FrameOptions::glDraw when
// given (a study's draw gate): the runner sees one draw of the GLSL method per band that has
// fragments and none of the C++ one, and the band draws equal one draw over the whole frame's
// fragments pixel for pixel (the bands keep the 2x2 quads whole).
TEST(Gl, BandDrawsRunThroughTheRunnerAndEqualAWholeFrameDraw) {
    const std::string method =
        R"([{"name":"g","glsl":")" + shaderDir() +
        R"(/layered.glsl","function":"ParallaxOcclusion","sampler":"heightMap",
        "uniforms":{"height_scale":"scale","height_bias":"bias","min_layers":8.0,
        "max_layers":32.0,"max_steps":0}}, "parallax"])";
    Scene s = test::planeScene(test::smoothTexture(32, 32), 0.06, -0.03, 55, 20, 150,
                               parseMethods(nlohmann::json::parse(method), "t", "m"));
    s.camera.height = 139;
    TruthBuilder builder(s);
    TruthPair truths = builder.build(s.displacement, s.truth.uncertainty);
    MethodTextureCache textures(s.height, s.uvExtent);
    const TimingSpec timing{
        .repeats = 1, .maxFragments = 0, .seed = 1, .glFragments = 4096, .glMinMs = 0};
    int draws = 0;
    FrameOptions frame{.keepImages = true,
                       .sinks = {},
                       .deferTiming = true,
                       .glDraw = [&](const std::function<void()>& draw) {
                           ++draws;
                           draw();
                       }};
    RenderResult r = renderView(s, s.view(), truths, s.methods, textures, timing, frame);
    const Camera camera = makeCamera(s);
    const FragmentList all = compactFragments(
        rasterize(drawnBaseMesh(s.base, camera), camera, {s.cullBackFaces, s.worldPerUv()}));
    std::set<int> bands;  // 139 rows: bands of 108 and 31
    for (int32_t p : all.pixel) bands.insert(p / 150 / bandRows(150));
    EXPECT_EQ(draws, int(bands.size()));
    EXPECT_GE(draws, 2);
    const Image2D<MethodPixel> whole =
        evaluateMethod(s.methods[0], all, textures.at(s.methods[0], s.displacement), 150, 139);
    int64_t compared = 0;
    for (size_t k = 0; k < whole.data.size(); ++k) {
        const MethodPixel &band = r.methods[0].pixels.data[k], &one = whole.data[k];
        ASSERT_EQ(band.covered, one.covered) << k;
        if (!one.covered) continue;
        EXPECT_EQ(band.uv.x, one.uv.x) << k;
        EXPECT_EQ(band.uv.y, one.uv.y) << k;
        ++compared;
    }
    EXPECT_GT(compared, 5000);
    // The GLSL method is timed with the C++ ones (deferTiming: by timeMethods), on a workload
    // of at least TimingSpec::glFragments.
    EXPECT_TRUE(std::isnan(r.methods[0].nsPerPixel));  // not measured yet
    timeMethods(r, textures, timing);
    EXPECT_GT(r.methods[0].nsPerPixel, 0);
    EXPECT_GE(r.methods[0].timing.fragments, 4096);
    EXPECT_EQ(r.methods[0].timing.repeats, 1);
    EXPECT_GE(r.methods[0].timing.p75, r.methods[0].timing.p25);
}

}  // namespace
}  // namespace pgt
