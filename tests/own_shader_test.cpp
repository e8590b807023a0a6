// The user's own shader as it ships (docs/methods.md "Your own shader"): HLSL through SPIR-V,
// a "call" instead of a glue file, "defines", the texture layouts engines pack height into,
// and a sampler the source leaves to pgt. Each is held to the built-in pom (written anew
// twins in tests/data) or to the layout's definition texel by texel; the bad input names its
// file, field and line. Runs in Mesa llvmpipe like tests/gl_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "core/error.h"
#include "gl_agree.h"
#include "heightfield/mipmaps.h"
#include "study/render.h"
#include "test_util.h"

namespace pgt {
namespace {

MethodConfig method(const nlohmann::json& entry) {
    return parseMethod(entry, test::testDataDir() + "/scene.json", "methods[0]");
}

// pom at its defaults (8 to 32 layers) on the bricks, and the checks of every twin.
struct PomCheck {
    Texture bricks = test::bricks(128);
    double s = 0.05, b = -0.025;
    test::Fragments in = test::randomFragments(20000, 5);
    MethodConfig cpu = parseMethod(nlohmann::json{{"name", "pom"}}, "test", "m");

    void expectEqual(const nlohmann::json& entry, const char* what) {
        const MethodConfig own = method(entry);
        const test::Agreement a = test::agree(cpu, own, bricks, s, b, in, 1e-3);
        std::printf(
            "%s: fragments %lld, over 1e-3 texel from pom %lld, max within %.2e; fetch "
            "count mismatches %lld\n",
            what, (long long)a.n, (long long)a.over, a.maxTexels, (long long)a.fetchMismatch);
        EXPECT_EQ(a.n, 20000) << what;
        EXPECT_LE(a.over, a.n / 100) << what;  // a march may flip a layer where floats tie
        EXPECT_LE(a.fetchMismatch, a.n / 100) << what;
    }
};

std::string data(const std::string& rel) { return test::testDataDir() + "/" + rel; }
// The shaders scenes/own_shader.json ships.
std::string scene(const std::string& file) {
    return test::testSourceDir() + "/../scenes/own_shader/" + file;
}

TEST(OwnShader, HlslTwinOfPomEqualsTheBuiltIn) {
    PomCheck pom;
    pom.expectEqual({{"name", "pom_hlsl"},
                     {"hlsl", data("hlsl/pom_twin.hlsl")},
                     {"function", "ParallaxOcclusion"},
                     {"sampler", "heightMap"},
                     {"uniforms",
                      {{"height_scale", "scale"},
                       {"height_bias", "bias"},
                       {"min_layers", 8.0},
                       {"max_layers", 32.0}}}},
                    "pom_twin.hlsl");
}

// An engine's function verbatim: typedefs and a height callback from an #include, cbuffer
// members set by name, V from the eye to the surface, an offset returned; the call adds it to
// uv. With the define that makes V point toward the eye, the call passes V as it is.
TEST(OwnShader, EngineStyleHlslRunsVerbatimThroughACall) {
    PomCheck pom;
    nlohmann::json entry = {{"name", "engine"},
                            {"hlsl", scene("engine_pom.hlsl")},
                            {"sampler", "_HeightMap"},
                            {"call", "uv + ParallaxOcclusionOffset(-V, s, b, uv)"},
                            {"uniforms", {{"_MinSteps", 8.0}, {"_MaxSteps", 32.0}}}};
    pom.expectEqual(entry, "engine_pom.hlsl, V negated in the call");
    entry["call"] = "uv + ParallaxOcclusionOffset(V, s, b, uv)";
    entry["defines"] = {{"ENGINE_VIEW_TOWARD_EYE", ""}};
    pom.expectEqual(entry, "engine_pom.hlsl, ENGINE_VIEW_TOWARD_EYE");
}

// WebGL 1 code reading the height from the alpha of a normal map whose sampler it leaves to
// the engine: "normal+height" gives A = h, pgt declares bumpSampler.
TEST(OwnShader, Es100HeightInTheNormalMapsAlphaEqualsPom) {
    PomCheck pom;
    nlohmann::json entry = {{"name", "alpha"},
                            {"glsl", scene("pom_alpha_es100.glsl")},
                            {"texture", "normal+height"},
                            {"sampler", "bumpSampler"},
                            {"call", "uv + occlusionOffset(-V, N, uv, s, b)"},
                            {"uniforms", {{"uMinLayers", 8.0}, {"uMaxLayers", 32.0}}}};
    pom.expectEqual(entry, "pom_alpha_es100.glsl");
    entry["call"] = "uv + occlusionOffset(V, N, uv, s, b)";
    entry["defines"] = {{"LEFT_HANDED_VIEW", 1}};
    pom.expectEqual(entry, "pom_alpha_es100.glsl, LEFT_HANDED_VIEW");
}

// Every channel of every layout, read at texel centres (no filtering): R = h or 1 - h for
// "height" and "depth" (G, B = 0, A = 1 as GL reads R32F), RGB = 0.5 + 0.5 m and A = h or
// 1 - h for the normal layouts, m being the normal map of the case's s and b.
TEST(OwnShader, EveryChannelOfEveryLayoutIsDefined) {
    const auto dir = std::filesystem::temp_directory_path() / "pgt_own_shader_layouts";
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "channels.glsl").string();
    std::ofstream(file) << "#version 330\nuniform sampler2D map;\nuniform int pair;\n"
                           "vec2 F(vec2 uv, vec3 V) {\n"
                           "    vec4 t = textureLod(map, uv, 0.0);\n"
                           "    return pair == 0 ? t.xy : t.zw;\n}\n";
    Texture t = test::bricks(32);
    const double s = 0.07, b = -0.03;
    DerivedMaps dm = makeDerivedMaps(t, s, b);
    test::Fragments in = test::randomFragments(512, 9);
    std::vector<size_t> texel(in.uv0.size());
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        const int x = int(k * 7 % 32), y = int(k * 13 / 7 % 32);
        texel[k] = size_t(y) * 32 + size_t(x);
        in.uv0[k] = Vec2f((float(x) + 0.5f) / 32, (float(y) + 0.5f) / 32);
    }
    for (const char* layout : {"height", "depth", "normal+height", "normal+depth"}) {
        const bool normal = std::string(layout).rfind("normal", 0) == 0;
        const bool depth = std::string(layout).find("depth") != std::string::npos;
        for (int pair = 0; pair < 2; ++pair) {
            const MethodConfig m = method({{"name", "channels"},
                                           {"glsl", file},
                                           {"function", "F"},
                                           {"sampler", "map"},
                                           {"texture", layout},
                                           {"uniforms", {{"pair", pair}}}});
            const GlslRun run = runGlsl(*m.shader(), MapRefs{.height = &t, .normal = &dm.normal}, s,
                                        b, in.uv0, in.view);
            for (size_t k = 0; k < in.uv0.size(); ++k) {
                const float h = t.texels[texel[k]], a = depth ? 1.0f - h : h;
                float want[4] = {a, 0.0f, 0.0f, 1.0f};
                if (normal)
                    for (int c = 0; c < 4; ++c)
                        want[c] =
                            c < 3 ? 0.5f + 0.5f * dm.normal.texels[texel[k] * 3 + size_t(c)] : a;
                EXPECT_NEAR(run.uv[k].x, want[2 * pair], 1e-6) << layout << " texel " << k;
                EXPECT_NEAR(run.uv[k].y, want[2 * pair + 1], 1e-6) << layout << " texel " << k;
            }
        }
    }
    std::filesystem::remove_all(dir);
}

// The packed layouts' mipmaps: with the height map's levels on, level 1 read at its texel
// centres holds A = the height map's level 1 and RGB = the 2x2 box of level 0's encoded
// normal.
TEST(OwnShader, PackedLayoutsHaveMipmaps) {
    const auto dir = test::tempDir("own_shader_mips");
    const std::string file = (dir / "level1.glsl").string();
    std::ofstream(file) << "#version 330\nuniform sampler2D map;\nuniform int pair;\n"
                           "vec2 F(vec2 uv, vec3 V) {\n"
                           "    vec4 t = textureLod(map, uv, 1.0);\n"
                           "    return pair == 0 ? t.xy : t.zw;\n}\n";
    Texture t = test::bricks(32);
    addMipmaps(t);
    ASSERT_TRUE(t.mips && !t.mips->empty());
    const Texture& level1 = (*t.mips)[0];
    ASSERT_EQ(level1.width, 16);
    DerivedMaps dm = makeDerivedMaps(t, 0.07, -0.03);
    test::Fragments in = test::randomFragments(256, 4);
    for (size_t k = 0; k < in.uv0.size(); ++k)
        in.uv0[k] = Vec2f((float(k % 16) + 0.5f) / 16, (float(k / 16 % 16) + 0.5f) / 16);
    float got[2][256][2];
    for (int pair = 0; pair < 2; ++pair) {
        const MethodConfig m = method({{"name", "mips"},
                                       {"glsl", file},
                                       {"function", "F"},
                                       {"sampler", "map"},
                                       {"texture", "normal+depth"},
                                       {"uniforms", {{"pair", pair}}}});
        const GlslRun run = runGlsl(*m.shader(), MapRefs{.height = &t, .normal = &dm.normal}, 0.07,
                                    -0.03, in.uv0, in.view);
        for (size_t k = 0; k < in.uv0.size(); ++k)
            got[pair][k][0] = run.uv[k].x, got[pair][k][1] = run.uv[k].y;
    }
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        const int x = int(k % 16), y = int(k / 16 % 16);
        float box[3] = {0, 0, 0};
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx)
                for (int c = 0; c < 3; ++c)
                    box[c] +=
                        0.25f *
                        (0.5f +
                         0.5f *
                             dm.normal.texels[(size_t(2 * y + dy) * 32 + size_t(2 * x + dx)) * 3 +
                                              size_t(c)]);
        EXPECT_NEAR(got[0][k][0], box[0], 1e-6) << k;
        EXPECT_NEAR(got[0][k][1], box[1], 1e-6) << k;
        EXPECT_NEAR(got[1][k][0], box[2], 1e-6) << k;
        EXPECT_NEAR(got[1][k][1], 1.0f - level1.texels[size_t(y) * 16 + size_t(x)], 1e-6) << k;
    }
}

// Bad input: exit-2 errors naming the file, the field and the user's line.
TEST(OwnShader, BadInputNamesTheFileFieldAndLine) {
    const auto dir = std::filesystem::temp_directory_path() / "pgt_own_shader_bad";
    std::filesystem::create_directories(dir);
    const std::string bad = (dir / "bad.hlsl").string();
    std::ofstream(bad) << "float2 F(float2 uv, float3 V) {\n    return uv + undeclared;\n}\n";
    Texture t = test::smoothTexture(8, 8);
    test::Fragments in = test::randomFragments(16, 3);
    auto errorOf = [&](const nlohmann::json& entry) -> std::string {
        try {
            const MethodConfig m = method(entry);
            runGlsl(*m.shader(), MapRefs{.height = &t}, 0.05, 0, in.uv0, in.view);
        } catch (const InputError& e) {
            return e.what();
        }
        return "no error";
    };
    const std::string hlslLine = errorOf({{"name", "bad"}, {"hlsl", bad}, {"function", "F"}});
    EXPECT_NE(hlslLine.find(bad + ":2:"), std::string::npos) << hlslLine;
    EXPECT_NE(hlslLine.find("undeclared"), std::string::npos) << hlslLine;
    const std::string pom = data("glsl/pom_es300.glsl");
    nlohmann::json glsl = {{"name", "es"}, {"glsl", pom}, {"sampler", "heightMap"}};
    glsl["call"] = "uv + nosuch(V)";
    std::string e = errorOf(glsl);
    EXPECT_NE(e.find(pom + ": call"), std::string::npos) << e;
    glsl["call"] = "vec3(uv, 0.0)";  // not a 2-vector
    e = errorOf(glsl);
    EXPECT_NE(e.find(": call"), std::string::npos) << e;
    nlohmann::json hlsl = {{"name", "h"}, {"hlsl", data("hlsl/pom_twin.hlsl")}};
    hlsl["call"] = "V.x";  // a scalar
    e = errorOf(hlsl);
    EXPECT_NE(e.find("call:"), std::string::npos) << e;
    nlohmann::json layout = {{"name", "es"}, {"glsl", pom}, {"texture", "rgba"}};
    e = errorOf(layout);
    EXPECT_NE(e.find("texture"), std::string::npos) << e;
    EXPECT_NE(e.find("normal+height"), std::string::npos) << e;
    nlohmann::json unused = {{"name", "es"}, {"glsl", pom}, {"sampler", "notThere"}};
    unused["call"] = "uv";  // pgt declares notThere; nothing samples it
    e = errorOf(unused);
    EXPECT_NE(e.find("notThere"), std::string::npos) << e;
    EXPECT_NE(e.find("not an active sampler2D"), std::string::npos) << e;
    const std::string include = (dir / "include.hlsl").string();
    std::ofstream(include) << "#include \"missing.hlsli\"\nfloat2 F(float2 uv, float3 V) { "
                              "return uv; }\n";
    e = errorOf({{"name", "i"}, {"hlsl", include}, {"function", "F"}});
    EXPECT_NE(e.find("missing.hlsli"), std::string::npos) << e;
    // glslang 12 crashes on this; pgt compiles in a child process and names the file.
    const std::string crash = (dir / "crash.hlsl").string();
    std::ofstream(crash) << "Texture2D T;\nSamplerState S;\n"
                            "float G(float2 uv) { return 1.0 -- T.SampleLevel(S, uv, 0).r; }\n"
                            "float2 F(float2 uv, float3 V) { return uv + V.xy * G(uv); }\n";
    e = errorOf({{"name", "c"}, {"hlsl", crash}, {"function", "F"}, {"sampler", "T"}});
    EXPECT_NE(e.find(crash + ": hlsl: glslang, the HLSL compiler, crashed"), std::string::npos)
        << e;
    e = errorOf({{"name", "v"}, {"hlsl", bad}, {"version", "300 es"}});
    EXPECT_NE(e.find("version"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

// The silent mistakes of docs/outputs.md "Warnings", each made on purpose: a shader that
// gives uv back, one that reads the (always 1) alpha of the height layout, one with V's sign
// flipped on a relief below the polygon, one that normalises V.xy (NaN head-on); the
// built-ins, right on the same frames, get none.
TEST(OwnShader, SilentMistakesAreWarned) {
    const auto dir = test::tempDir("own_shader_warnings");
    const std::string head =
        "#version 330\nuniform sampler2D depthMap;\nvec2 F(vec2 uv, vec3 V) {\n";
    const std::map<std::string, std::string> bodies = {
        {"same", "    return uv - V.xy / V.z * 0.05 * texture(depthMap, uv).g;\n}\n"},
        {"alpha", "    return uv - V.xy / V.z * 0.05 * texture(depthMap, uv).a;\n}\n"},
        {"flipped", "    return uv + V.xy / V.z * 0.05 * (1.0 - texture(depthMap, uv).r);\n}\n"},
        {"headon", "    return uv - normalize(V.xy) * 0.01 * texture(depthMap, uv).r;\n}\n"}};
    nlohmann::json entries = {"none", "parallax", "pom"};
    for (const auto& [name, body] : bodies) {
        std::ofstream(dir / (name + ".glsl")) << head << body;
        entries.push_back(
            {{"name", name}, {"glsl", (dir / (name + ".glsl")).string()}, {"function", "F"}});
    }
    const std::vector<MethodConfig> methods = parseMethods(entries, "test", "methods");
    auto kinds = [&](double theta) {
        // The relief below the polygon: s 0.05, b -0.05.
        Scene sc =
            test::planeScene(test::smoothTexture(32, 32), 0.05, -0.05, theta, 30, 48, methods);
        sc.truth.uncertainty = false;
        const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
        std::map<std::string, std::string> out;
        for (const MethodFrame& m : r.methods) out[m.config.name] = warningKinds(m.warnings);
        return out;
    };
    const auto oblique = kinds(40);
    EXPECT_EQ(oblique.at("same"), "no_offset");
    EXPECT_EQ(oblique.at("alpha"), "constant_offset");
    EXPECT_EQ(oblique.at("flipped"), "toward_eye");
    EXPECT_EQ(oblique.at("headon"), "");
    for (const char* fine : {"none", "parallax", "pom"}) EXPECT_EQ(oblique.at(fine), "") << fine;
    const auto headOn = kinds(0);
    EXPECT_EQ(headOn.at("headon"), "nonfinite_head_on");
    for (const char* fine : {"none", "parallax", "pom", "same", "alpha", "flipped"})
        EXPECT_EQ(headOn.at(fine), "") << fine;  // nothing to see without V.xy
}

}  // namespace
}  // namespace pgt
