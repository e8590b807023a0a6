// The user's own shader as it ships (docs/methods.md "Your own shader"): HLSL through SPIR-V,
// a "call" instead of a glue file, "defines", the texture layouts engines pack height into,
// and a sampler the source leaves to pgt. Each is held to the built-in pom (written anew
// twins in tests/data) or to the layout's definition texel by texel; the bad input names its
// file, field and line. Runs in Mesa llvmpipe like tests/gl_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>

#include "core/error.h"
#include "core/json_read.h"
#include "frame/render.h"
#include "gl_agree.h"
#include "heightfield/mipmaps.h"
#include "methods/shader/shader_config.h"
#include "methods/shader/shader_words.h"
#include "methods/shader/source_text.h"
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
// The uniforms of pgt's pom written as a user's file (tests/data): s and b bound, 8-32 layers.
nlohmann::json pomUniforms() {
    return {{"height_scale", "scale"},
            {"height_bias", "bias"},
            {"min_layers", 8.0},
            {"max_layers", 32.0}};
}
// pgt's pom (docs/model.md §6b) as a body's statements: `start`, the lines that move uv to the
// top of the relief (and declare what they need), then the march with `scale` the name of s
// and `depthAt(P)` the depth read at P.
nlohmann::json pomBody(std::vector<std::string> start, const std::string& scale,
                       const std::function<std::string(const std::string&)>& depthAt) {
    for (const std::string& line :
         {std::string("float numLayers = mix(32.0, 8.0, abs(V.z));"),
          "vec2 delta = V.xy / V.z * " + scale + " / numLayers;",
          "float depth = " + depthAt("uv") + ", layer = 0.0;",
          std::string("while (layer < depth) {"), std::string("    uv -= delta;"),
          "    depth = " + depthAt("uv") + ";", std::string("    layer += 1.0 / numLayers;"),
          std::string("}"), std::string("vec2 prev = uv + delta;"),
          "float after = depth - layer, before = " + depthAt("prev") +
              " - layer + 1.0 / numLayers;",
          std::string("return mix(uv, prev, after / (after - before));")})
        start.push_back(line);
    return start;
}
std::string fileDepthAt(const std::string& p) { return "depthAt(" + p + ")"; }

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
                     {"uniforms", pomUniforms()}},
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

// Engines' files as they ship, in each style of docs/methods.md "Your engine's file" (pgt's own
// files in those styles, tests/data): each equals the built-in pom with a scene entry only.
// DX9 / Cg HLSL: a sampler2D global read with tex2Dlod; the file has a UTF-8 byte-order mark
// and CRLF line ends.
TEST(EngineFiles, Dx9SamplerWithByteOrderMarkAndCrlfEqualsPom) {
    std::ifstream raw(data("hlsl/pom_dx9.hlsl"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(raw)), {});
    ASSERT_EQ(bytes.rfind("\xEF\xBB\xBF", 0), 0u);  // the file is as a Windows editor saves it
    ASSERT_NE(bytes.find("\r\n"), std::string::npos);
    PomCheck pom;
    pom.expectEqual({{"name", "dx9"},
                     {"hlsl", data("hlsl/pom_dx9.hlsl")},
                     {"function", "ParallaxOcclusion"},
                     {"sampler", "heightMap"},
                     {"uniforms", pomUniforms()}},
                    "pom_dx9.hlsl");
}

// A function that answers through an inout float4 and takes its texture and sampler as
// parameters (the sampler defaulting to a global), with enums and an include with
// #pragma once: run through "body", the texture declared by pgt.
TEST(EngineFiles, InoutFunctionThroughABodyEqualsPom) {
    PomCheck pom;
    pom.expectEqual(
        {{"name", "inout"},
         {"hlsl", data("hlsl/pom_inout.hlsl")},
         {"sampler", "heightTex"},
         {"body",
          {"float4 uvsets = uv.xyxy;",
           "ParallaxOcclusion_Impl(uvsets, V, s, b, 8.0, 32.0, heightTex);", "return uvsets.zw;"}}},
        "pom_inout.hlsl, body");
    // The same with the sampler passed: "sampler_state" names the one pgt declares.
    pom.expectEqual(
        {{"name", "inout"},
         {"hlsl", data("hlsl/pom_inout.hlsl")},
         {"sampler", "heightTex"},
         {"sampler_state", "mySampler"},
         {"body",
          "float4 uvsets = uv.xyxy;\nParallaxOcclusion_Impl(uvsets, V, s, b, 8.0, 32.0, heightTex, "
          "4u, mySampler);\nreturn uvsets.xy;"}},
        "pom_inout.hlsl, body with the sampler");
}

// GLSL split over files with #include (one file included twice, kept once by #pragma once),
// the height in G ("texture": "height.g"), a byte-order mark and CRLF.
TEST(EngineFiles, GlslIncludeAndHeightInGreenEqualPom) {
    PomCheck pom;
    pom.expectEqual({{"name", "inc"},
                     {"glsl", data("glsl/pom_include.glsl")},
                     {"function", "ParallaxOcclusion"},
                     {"sampler", "packedMap"},
                     {"texture", "height.g"},
                     {"uniforms", pomUniforms()}},
                    "pom_include.glsl, height.g");
}

// "include_paths": the file alone in a folder of its own, its includes found in a folder the
// entry names (relative to the scene file), in GLSL and HLSL; a missing folder is refused.
TEST(EngineFiles, IncludesAreFoundOnTheIncludePaths) {
    const auto dir = test::tempDir("include_paths");
    std::filesystem::create_directories(dir / "shaders");
    std::filesystem::copy_file(data("glsl/pom_include.glsl"), dir / "shaders/pom_include.glsl");
    std::filesystem::copy_file(data("hlsl/pom_inout.hlsl"), dir / "shaders/pom_inout.hlsl");
    const std::string glslDir = std::filesystem::path(data("glsl/pom_steps.glsl")).parent_path(),
                      hlslDir = std::filesystem::path(data("hlsl/pom_march.hlsli")).parent_path();
    PomCheck pom;
    pom.expectEqual({{"name", "inc"},
                     {"glsl", (dir / "shaders/pom_include.glsl").string()},
                     {"include_paths", {glslDir}},
                     {"function", "ParallaxOcclusion"},
                     {"sampler", "packedMap"},
                     {"texture", "height.g"},
                     {"uniforms", pomUniforms()}},
                    "pom_include.glsl alone, include_paths");
    pom.expectEqual(
        {{"name", "inout"},
         {"hlsl", (dir / "shaders/pom_inout.hlsl").string()},
         {"include_paths", {hlslDir}},
         {"sampler", "heightTex"},
         {"body",
          {"float4 uvsets = uv.xyxy;",
           "ParallaxOcclusion_Impl(uvsets, V, s, b, 8.0, 32.0, heightTex);", "return uvsets.zw;"}}},
        "pom_inout.hlsl alone, include_paths");
    try {
        method({{"name", "x"},
                {"glsl", (dir / "shaders/pom_include.glsl").string()},
                {"include_paths", {"nowhere"}}});
        ADD_FAILURE() << "a missing include folder was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("include_paths[0]"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

// A Vulkan-style fragment shader as it ships (tests/data/glsl/vulkan_pom.frag): set and binding
// layouts, a uniform block and a push-constant block whose members the entry sets by
// "INSTANCE.MEMBER", located stage inputs and output (plain globals a body may assign), an
// array texture; its function through a body, with the height as depth in the normal map's
// alpha. It equals pom with no wrapper (issue 54).
TEST(EngineFiles, VulkanStyleGlslRunsAsShipped) {
    PomCheck pom;
    nlohmann::json entry = {{"name", "vk"},
                            {"glsl", data("glsl/vulkan_pom.frag")},
                            {"sampler", "sNormalHeightMap"},
                            {"texture", "normal+depth"},
                            {"uniforms",
                             {{"ubo.heightScale", "scale"},
                              {"ubo.parallaxBias", "bias"},
                              {"ubo.maxLayers", 32.0},
                              {"pc.minLayers", 8.0}}},
                            {"body", {"inUV = uv;", "return parallaxOcclusion(inUV, V);"}}};
    pom.expectEqual(entry, "vulkan_pom.frag");
    // The text the GL gets keeps every line in its place.
    std::ifstream in(data("glsl/vulkan_pom.frag"));
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    const std::string gl = vulkanGlslForGl(text);
    EXPECT_EQ(std::count(gl.begin(), gl.end(), '\n'), std::count(text.begin(), text.end(), '\n'));
    EXPECT_EQ(gl.find("set ="), std::string::npos) << gl;
    EXPECT_EQ(gl.find("push_constant"), std::string::npos) << gl;
    EXPECT_NE(gl.find("struct UBO"), std::string::npos) << gl;
    EXPECT_NE(gl.find("uniform PushConsts pc;"), std::string::npos) << gl;
    // A block without an instance name: its members become uniforms.
    const std::string members =
        vulkanGlslForGl("layout(binding = 0) uniform B {\n    float k;\n    vec2 m;\n};\n");
    EXPECT_NE(members.find("\n    uniform float k;\n    uniform vec2 m;\n"), std::string::npos)
        << members;
    EXPECT_EQ(members.find_first_of("{}"), std::string::npos) << members;
    EXPECT_EQ(std::count(members.begin(), members.end(), '\n'), 4);
}

// A generator's shader has no file (Panda3D's): a "body" alone, in GLSL (default) or HLSL
// ("language"), with the sampler pgt declares and s, b; it equals pom as a file would.
TEST(EngineFiles, ABodyWithoutAFileEqualsPom) {
    PomCheck pom;
    pom.expectEqual({{"name", "generated"},
                     {"version", "330"},
                     {"body", pomBody({"uv = uv + V.xy / V.z * (s + b);"}, "s",
                                      [](const std::string& p) {
                                          return "(1.0 - textureLod(depthMap, " + p + ", 0.0).r)";
                                      })}},
                    "a body without a file (GLSL)");
    const MethodConfig m = method({{"name", "g"}, {"language", "hlsl"}, {"body", "return uv;"}});
    EXPECT_TRUE(m.shader()->hlsl);
    EXPECT_FALSE(m.shader()->ownFile);
    EXPECT_EQ(toJson(m).at("language"), "hlsl");
    EXPECT_FALSE(toJson(m).contains("hlsl"));
    // Without a body it is no method: the error says what is missing.
    try {
        method({{"name", "g"}, {"language", "glsl"}, {"call", "uv"}});
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("body"), std::string::npos) << e.what();
    }
}

// A whole GL 2 fragment shader (varyings, gl_FragColor, its own main()), whose parallax is
// statements in main(): the same statements in "body".
TEST(EngineFiles, WholeFragmentShaderThroughABodyEqualsPom) {
    PomCheck pom;
    pom.expectEqual({{"name", "whole"},
                     {"glsl", data("glsl/whole_frag.glsl")},
                     {"sampler", "uHeightMap"},
                     {"uniforms", {{"uHeightScale", "scale"}, {"uHeightBias", "bias"}}},
                     {"body", pomBody({"uv = uv + V.xy / V.z * (uHeightScale + uHeightBias);"},
                                      "uHeightScale", fileDepthAt)}},
                    "whole_frag.glsl, body");
}

// A body's locals may take the names pgt hands it (N, V, s, b), as an engine's code does
// (`vec3 N = ...`, `V = normalize(V)`): the body has a scope of its own (issue 54).
TEST(EngineFiles, ABodysLocalsMayTakePgtsNames) {
    PomCheck pom;
    pom.expectEqual({{"name", "whole"},
                     {"glsl", data("glsl/whole_frag.glsl")},
                     {"sampler", "uHeightMap"},
                     {"uniforms", {{"uHeightScale", "scale"}, {"uHeightBias", "bias"}}},
                     {"body", pomBody({"vec3 N = vec3(0.0, 0.0, 1.0);", "vec3 V = V;",
                                       "float s = uHeightScale;",
                                       "uv = uv + V.xy / dot(V, N) * (s + uHeightBias);"},
                                      "s", fileDepthAt)}},
                    "whole_frag.glsl, body with locals N, V, s");
    pom.expectEqual(
        {{"name", "inout"},
         {"hlsl", data("hlsl/pom_inout.hlsl")},
         {"sampler", "heightTex"},
         {"body",
          {"float3 N = float3(0.0, 0.0, 1.0);", "float3 V = V;", "float4 uvsets = uv.xyxy;",
           "ParallaxOcclusion_Impl(uvsets, V, s, b, 8.0, 32.0, heightTex);", "return uvsets.zw;"}}},
        "pom_inout.hlsl, body with locals N, V");
}

// Every channel of every layout, read at texel centres (no filtering): R = h or 1 - h for
// "height" and "depth" (G, B = 0, A = 1 as GL reads R32F), RGB = 0.5 + 0.5 m and A = h or
// 1 - h for the normal layouts, m being the normal map of the case's s and b; "height.C" and
// "depth.C" the value in the channels C, the others R, G, B 0 and A 1.
TEST(OwnShader, EveryChannelOfEveryLayoutIsDefined) {
    const auto dir = test::tempDir("own_shader_layouts");
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
    for (const char* layout : {"height", "depth", "normal+height", "normal+depth", "height.g",
                               "depth.a", "height.rgb", "depth.rb", "height.rgba"}) {
        const bool normal = std::string(layout).rfind("normal", 0) == 0;
        const bool depth = std::string(layout).find("depth") != std::string::npos;
        const size_t dot = std::string(layout).find('.');
        const std::string channels = dot == std::string::npos ? "" : layout + dot + 1;
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
                if (!channels.empty())  // the named channels hold it, the others R, G, B 0, A 1
                    for (int c = 0; c < 4; ++c)
                        want[c] = channels.find("rgba"[c]) != std::string::npos ? a
                                  : c == 3                                      ? 1.0f
                                                                                : 0.0f;
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
    const auto dir = test::tempDir("own_shader_bad");
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
    std::string e;
    // A file's own #line (generated code, an engine's shader cache): the message names the
    // line's place in the file, and what its #line said of it (issue 54: "pgt prelude:5").
    const std::string lined = (dir / "lined.glsl").string(),
                      linedHlsl = (dir / "lined.hlsl").string();
    std::ofstream(lined) << "uniform sampler2D depthMap;\n#line 500\nvec2 F(vec2 uv, vec3 V) {\n"
                            "    return uv + undeclared;\n}\n";
    std::ofstream(linedHlsl) << "#line 500 \"gen.hlsl\"\nfloat2 F(float2 uv, float3 V) {\n"
                                "    return uv + undeclared;\n}\n";
    for (const auto& [key, file] :
         {std::pair<std::string, std::string>{"glsl", lined}, {"hlsl", linedHlsl}}) {
        e = errorOf({{"name", "l"}, {key, file}, {"function", "F"}});
        const std::string at = key == "glsl" ? ":4:" : ":3";
        EXPECT_NE(e.find(file + at), std::string::npos) << e;
        EXPECT_NE(e.find(key == "glsl" ? "(its #line: 501)" : "(its #line: \"gen.hlsl\":501)"),
                  std::string::npos)
            << e;
        EXPECT_EQ(e.find("prelude"), std::string::npos) << e;
    }
    const std::string pom = data("glsl/pom_es300.glsl");
    nlohmann::json glsl = {{"name", "es"}, {"glsl", pom}, {"sampler", "heightMap"}};
    glsl["call"] = "uv + nosuch(V)";
    e = errorOf(glsl);
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
    // A void function as a call: the message says so and names "body".
    const std::string inout = data("hlsl/pom_inout.hlsl");
    e = errorOf({{"name", "v"}, {"hlsl", inout}, {"call", "ParallaxOcclusion_Impl(uv, V)"}});
    EXPECT_NE(e.find("returns void"), std::string::npos) << e;
    EXPECT_NE(e.find("\"body\""), std::string::npos) << e;
    // A body without a return; a body and a call; a body's error names its line.
    e = errorOf({{"name", "b"}, {"hlsl", inout}, {"body", "float2 x = uv;"}});
    EXPECT_NE(e.find("has no return"), std::string::npos) << e;
    e = errorOf({{"name", "b"}, {"hlsl", inout}, {"body", "return uv;"}, {"call", "uv"}});
    EXPECT_NE(e.find("not both"), std::string::npos) << e;
    e = errorOf({{"name", "b"}, {"glsl", pom}, {"body", {"vec2 x = uv;", "return nosuch;"}}});
    EXPECT_NE(e.find(pom + ": body:2:"), std::string::npos) << e;
    e = errorOf({{"name", "b"}, {"hlsl", inout}, {"body", {"float2 x = uv;", "return nosuch;"}}});
    EXPECT_NE(e.find(inout + ": body:2"), std::string::npos) << e;
    // Channels only of "height" and "depth", in r, g, b, a order; sampler_state is HLSL's.
    for (const char* texture : {"normal+height.a", "height.gr", "height.x", "height."}) {
        e = errorOf({{"name", "c"}, {"glsl", pom}, {"texture", texture}});
        EXPECT_NE(e.find("texture"), std::string::npos) << texture << ": " << e;
    }
    e = errorOf({{"name", "c"}, {"glsl", pom}, {"sampler_state", "s"}});
    EXPECT_NE(e.find("sampler_state"), std::string::npos) << e;
    // A GLSL file that includes itself stops at the depth limit, naming the file; an included
    // file's error names that file and its own line.
    const std::string self = (dir / "self.glsl").string();
    std::ofstream(self) << "#include \"self.glsl\"\nvec2 F(vec2 uv, vec3 V) { return uv; }\n";
    e = errorOf({{"name", "s"}, {"glsl", self}, {"function", "F"}});
    EXPECT_NE(e.find("self.glsl"), std::string::npos) << e;
    EXPECT_NE(e.find("includes nest more than 32 deep"), std::string::npos) << e;
    std::ofstream(dir / "part.glsl") << "// a helper\nfloat helper() { return nosuch; }\n";
    const std::string top = (dir / "top.glsl").string();
    std::ofstream(top) << "#include \"part.glsl\"\nvec2 F(vec2 uv, vec3 V) { return uv; }\n";
    e = errorOf({{"name", "t"}, {"glsl", top}, {"function", "F"}, {"sampler", ""}});
    EXPECT_NE(e.find((dir / "part.glsl").string() + ":2:"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

// pgt's passes over a file follow the preprocessor: an include under a branch that is
// certainly skipped (#ifdef of a name nothing defines, #if 0) is not read (a missing file, a
// self-include), one whose name the entry defines is (and its absence named), a #version in a
// comment is none, and a #pragma once under #if 0 is none.
TEST(OwnShader, IncludesFollowThePreprocessorsConditionals) {
    const auto dir = test::tempDir("conditional_includes");
    std::ofstream(dir / "lib.glsl") << "vec2 k() { return vec2(0.0); }\n";
    std::ofstream(dir / "a.glsl") << "/* an old header:\n#version 999\n*/\n#version 330\n"
                                     "#ifdef USE_EXTRA\n#include \"missing.glsl\"\n#endif\n"
                                     "#if 0\n#include \"a.glsl\"\n#else\n#include \"lib.glsl\"\n"
                                     "#endif\n// #include \"commented.glsl\"\n"
                                     "vec2 F(vec2 uv, vec3 V) { return uv + k(); }\n";
    const std::string file = (dir / "a.glsl").string();
    auto parse = [&](const nlohmann::json& extra) {
        nlohmann::json e = {{"name", "a"}, {"glsl", file}, {"function", "F"}, {"sampler", ""}};
        e.update(extra);
        return parseMethods(nlohmann::json::array({e}), "test", "methods");
    };
    const std::vector<MethodConfig> plain = parse(nlohmann::json::object());
    const GlslSpec& spec = *plain[0].shader();
    EXPECT_EQ(spec.version, "330");
    EXPECT_NE(spec.source.find("vec2 k()"), std::string::npos);  // lib.glsl, the #else arm
    EXPECT_EQ(spec.source.find("\n#include"), std::string::npos) << spec.source;
    try {
        parse({{"defines", {{"USE_EXTRA", "1"}}}});
        ADD_FAILURE() << "an include the entry's define asks for was not read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.glsl"), std::string::npos) << e.what();
    }
    // What an include defines under a branch pgt cannot judge (GL_ES: the compiler's) is
    // unsure: an #ifndef of it is not skipped. A missing include there becomes an #error
    // line, which the compiler's preprocessor skips or names. A hostile #if line (100,000
    // '!') is read without recursion.
    std::ofstream(dir / "es.glsl") << "#define LOW 1\n";
    std::ofstream(dir / "desktop.glsl") << "float desk() { return 1.0; }\n";
    std::ofstream(dir / "b.glsl") << "#ifdef GL_ES\n#include \"es.glsl\"\n#endif\n"
                                     "#ifndef LOW\n#include \"desktop.glsl\"\n#endif\n"
                                     "#ifdef GL_ES\n#include \"gone.glsl\"\n#endif\n#if "
                                  << std::string(100000, '!') << "1\n#endif\n"
                                  << "vec2 F(vec2 uv, vec3 V) { return uv * desk(); }\n";
    nlohmann::json b = {
        {"name", "b"}, {"glsl", (dir / "b.glsl").string()}, {"function", "F"}, {"sampler", ""}};
    const std::vector<MethodConfig> unsure =
        parseMethods(nlohmann::json::array({b}), "test", "methods");
    EXPECT_NE(unsure[0].shader()->source.find("float desk()"), std::string::npos);
    EXPECT_NE(unsure[0].shader()->source.find("#error pgt cannot read the include gone.glsl"),
              std::string::npos);
    std::string once = "#if 0\n#pragma once\n#endif\nfloat f;\n";
    EXPECT_FALSE(takePragmaOnce(once));
    once = "#if 1\n#pragma once\n#endif\n";
    EXPECT_TRUE(takePragmaOnce(once));
    once = "/*\n#pragma once\n*/\n";
    EXPECT_FALSE(takePragmaOnce(once));
}

// The silent mistakes of docs/outputs.md "Warnings", each made on purpose: a shader that
// gives uv back, one that reads the (always 1) alpha of the height layout, one with V's sign
// flipped on a relief below the polygon, one that normalises V.xy (NaN head-on), one that
// marches the wrong way twice as far (worse than no parallax); the built-ins, right on the
// same frames, get none.
TEST(OwnShader, SilentMistakesAreWarned) {
    const auto dir = test::tempDir("own_shader_warnings");
    const std::string head =
        "#version 330\nuniform sampler2D depthMap;\nvec2 F(vec2 uv, vec3 V) {\n";
    const std::map<std::string, std::string> bodies = {
        {"same", "    return uv - V.xy / V.z * 0.05 * texture(depthMap, uv).g;\n}\n"},
        {"alpha", "    return uv - V.xy / V.z * 0.05 * texture(depthMap, uv).a;\n}\n"},
        {"flipped", "    return uv + V.xy / V.z * 0.05 * (1.0 - texture(depthMap, uv).r);\n}\n"},
        {"headon", "    return uv - normalize(V.xy) * 0.01 * texture(depthMap, uv).r;\n}\n"},
        {"inverted", "    return uv + V.xy / V.z * 0.1 * texture(depthMap, uv).r;\n}\n"}};
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
    EXPECT_EQ(oblique.at("inverted"), "toward_eye;worse_than_none");
    for (const char* fine : {"none", "parallax", "pom"}) EXPECT_EQ(oblique.at(fine), "") << fine;
    const auto headOn = kinds(0);
    EXPECT_EQ(headOn.at("headon"), "nonfinite_head_on");
    for (const char* fine : {"none", "parallax", "pom", "same", "alpha", "flipped", "inverted"})
        EXPECT_EQ(headOn.at(fine), "") << fine;  // nothing to see without V.xy
}

// A shader that reads the (always 1) alpha of the height layout offsets every pixel alike at
// every azimuth, not only where V has a zero component: constant_offset at each phi, on an
// infinite plane seen whole ("fill": uv up to several units, where uv' rounds in float).
TEST(OwnShader, ConstantOffsetIsWarnedAtEveryAzimuth) {
    const auto dir = test::tempDir("constant_offset");
    std::ofstream(dir / "alpha.glsl")
        << "#version 330\nuniform sampler2D depthMap;\n"
           "vec2 F(vec2 uv, vec3 V) {\n"
           "    return uv - V.xy / V.z * 0.05 * texture(depthMap, uv).a;\n}\n";
    for (double phi : {0.0, 20.0, 30.0, 45.0, 60.0, 90.0, 137.0}) {
        nlohmann::json scene = nlohmann::json::parse(R"({
            "heightmap": {"procedural": "bricks", "size": [64, 64]},
            "displacement": {"scale": 0.05, "bias": -0.05},
            "base": {"type": "plane", "infinite": true, "tiling": 4},
            "camera": {"type": "orthographic", "theta": 45, "frame": "fill", "resolution": [32, 32]},
            "truth": {"rate": 1, "uncertainty": false}})");
        scene["camera"]["phi"] = phi;
        scene["methods"] = {{{"name", "alpha"},
                             {"glsl", (dir / "alpha.glsl").string()},
                             {"function", "F"},
                             {"texture", "height"}}};
        const RenderResult r =
            renderFrame(parseScene(scene, (dir / "s.json").string()), {.timingRepeats = 0});
        EXPECT_EQ(warningKinds(r.methods[0].warnings), "constant_offset") << "phi " << phi;
    }
}

// worse_than_none names the cause that fits the data: the same parallax (uv + V.xy / V.z
// (s h + b)) with its own b set (0.1 where the surface's is -0.05) is an amplitude or bias
// mismatch, with its sign turned it runs against the relief, and on the surface's own (s, b)
// at 80 degrees (bricks, s 0.1, b -0.1) it is the documents' known grazing breakdown, its own
// kind (an orthographic view's mean angle is 80 to a rounding).
TEST(OwnShader, WorseThanNoneNamesItsCause) {
    const auto dir = test::tempDir("own_shader_causes");
    std::ofstream(dir / "p.glsl")
        << "#version 330\nuniform sampler2D depthMap;\n"
           "vec2 F(vec2 uv, vec3 V, float s, float b) {\n"
           "    return uv + V.xy / V.z * (s * texture(depthMap, uv).r + b);\n}\n"
           "vec2 G(vec2 uv, vec3 V, float s, float b) {\n"
           "    return uv - V.xy / V.z * (s * texture(depthMap, uv).r + b);\n}\n";
    const std::string file = (dir / "p.glsl").string();
    const nlohmann::json methods = {
        "none",
        {{"name", "right"}, {"glsl", file}, {"call", "F(uv, V, s, b)"}, {"texture", "height"}},
        {{"name", "doubled"},
         {"glsl", file},
         {"call", "F(uv, V, s, b)"},
         {"texture", "height"},
         {"bias", 0.1}},
        {{"name", "against"}, {"glsl", file}, {"call", "G(uv, V, s, b)"}, {"texture", "height"}}};
    auto warned = [&](double theta, double bias) {
        nlohmann::json scene = nlohmann::json::parse(R"({
            "heightmap": {"procedural": "bricks", "size": [64, 64]},
            "base": {"type": "plane", "infinite": true},
            "camera": {"type": "orthographic", "phi": 0, "frame": "fill", "resolution": [48, 48]},
            "truth": {"rate": 1, "uncertainty": false}})");
        scene["displacement"] = {{"scale", 0.1}, {"bias", bias}};
        scene["camera"]["theta"] = theta;
        scene["methods"] = methods;
        const RenderResult r =
            renderFrame(parseScene(scene, (dir / "s.json").string()), {.timingRepeats = 0});
        std::map<std::string, MethodWarning> out;
        for (const MethodFrame& m : r.methods)
            for (const MethodWarning& w : m.warnings)
                if (w.kind == "worse_than_none" || w.kind == "grazing_breakdown")
                    out[m.config.name] = w;
        return out;
    };
    const auto at60 = warned(60, -0.05);
    EXPECT_EQ(at60.count("right"), 0u);
    ASSERT_EQ(at60.count("doubled"), 1u);
    EXPECT_NE(at60.at("doubled").text.find("amplitude or bias mismatch"), std::string::npos)
        << at60.at("doubled").text;
    ASSERT_EQ(at60.count("against"), 1u);
    EXPECT_NE(at60.at("against").text.find("run against the relief"), std::string::npos)
        << at60.at("against").text;
    const auto at80 = warned(80, -0.1);
    ASSERT_EQ(at80.count("right"), 1u);
    EXPECT_EQ(at80.at("right").kind, "grazing_breakdown") << at80.at("right").text;
    EXPECT_NE(at80.at("right").text.find("mean theta 80 degrees"), std::string::npos);
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// A shader whose answer tells which of the entry's settings reached the compiled program: the
// engine inputs, a define, a uniform left at its linked value unless set, the API's y.
constexpr const char* kVariantShader = R"(uniform sampler2D heightMap;
uniform float k;
vec2 F(vec2 uv, vec3 V) {
    float h = texture(heightMap, uv).r;
    vec2 r = uv + V.xy / V.z * (0.05 * h - 0.025);
#ifdef PGT_ENGINE_INPUTS
    r += 0.01;
#endif
#ifdef EXTRA
    r += EXTRA;
#endif
    r.x += k;
    r.y += 4.0 * dFdy(uv).y;
    return r;
}
)";

// One frame of `methods` on a small plane (orthographic, 32 x 32).
RenderResult renderVariants(const std::filesystem::path& dir, const nlohmann::json& methods) {
    const Scene s = parseScene(nlohmann::json::parse(R"({
        "heightmap": {"procedural": "sine", "size": [32, 32]},
        "displacement": {"scale": 0.05, "bias": -0.025}, "base": {"type": "plane"},
        "camera": {"type": "orthographic", "theta": 40, "phi": 25, "resolution": [32, 32]},
        "truth": {"rate": 1, "uncertainty": false}, "methods": )" +
                                                     methods.dump() + "}"),
                               (dir / "s.json").string());
    return renderFrame(s, {.timingRepeats = 0});
}

// The program's identity is its text: every entry setting that reaches the compiled program
// (engine inputs, defines, a call, the API, uniforms it sets or leaves) gives the same answer
// alone and listed before or after any other, pairwise in both orders. Before, the program
// cache keyed a hand list of settings that left out the engine inputs, and programs shared by
// two entries kept the first one's uniforms.
TEST(OwnShader, EveryEntrySettingGivesTheSameAnswerInAnyOrder) {
    auto dir = test::tempDir("variants");
    std::ofstream(dir / "variant.glsl") << kVariantShader;
    auto entry = [](const char* label) {
        return nlohmann::json{
            {"name", label}, {"glsl", "variant.glsl"}, {"function", "F"}, {"sampler", "heightMap"}};
    };
    std::vector<nlohmann::json> variants = {entry("plain"),   entry("engine"), entry("defined"),
                                            entry("uniform"), entry("d3d"),    entry("call")};
    variants[1]["inputs"] = "engine";
    variants[2]["defines"] = {{"EXTRA", "0.02"}};
    variants[3]["uniforms"] = {{"k", 0.03}};
    variants[4]["api"] = "d3d";
    variants[5]["call"] = "F(uv, V) + vec2(0.005)";
    std::vector<std::vector<Vec2d>> alone;
    for (const auto& v : variants) {
        const RenderResult r = renderVariants(dir, nlohmann::json::array({v}));
        alone.emplace_back();
        for (const MethodPixel& p : r.methods[0].pixels.data) alone.back().push_back(p.uv);
    }
    // The variants differ from each other (each setting changes the answer).
    for (size_t i = 1; i < variants.size(); ++i) EXPECT_NE(alone[i][100], alone[0][100]) << i;
    for (size_t i = 0; i < variants.size(); ++i)
        for (size_t j = 0; j < variants.size(); ++j) {
            if (i == j) continue;
            const RenderResult r =
                renderVariants(dir, nlohmann::json::array({variants[i], variants[j]}));
            for (size_t m = 0; m < 2; ++m) {
                const size_t which = m == 0 ? i : j;
                int differ = 0;
                for (size_t k = 0; k < alone[which].size(); ++k) {
                    const Vec2d a = alone[which][k], b = r.methods[m].pixels.data[k].uv;
                    differ += !(a == b || (std::isnan(a.x) && std::isnan(b.x)));
                }
                EXPECT_EQ(differ, 0) << r.methods[m].config.label << " after/before "
                                     << variants[m == 0 ? j : i]["name"];
            }
        }
    std::filesystem::remove_all(dir);
}

// The default scene's method list in another order gives every label the same row.
TEST(OwnShader, TheDefaultScenesMethodsInAnyOrderGiveTheSameRows) {
    nlohmann::json json;
    std::ifstream(test::sceneDir() + "/default.json") >> json;
    json["camera"]["resolution"] = {40, 40};
    json["truth"] = {{"rate", 1}, {"uncertainty", false}};
    json["light"] = nullptr;
    json.erase("light");
    json.erase("sweep");
    auto rows = [&](const nlohmann::json& methods) {
        nlohmann::json j = json;
        j["methods"] = methods;
        const Scene s = parseScene(j, test::sceneDir() + "/default.json");
        const RenderResult r = renderFrame(s, {.timingRepeats = 0});
        std::map<std::string, std::pair<double, double>> out;
        for (const MethodFrame& m : r.methods)
            out[m.config.label] = {m.stats.error.mean, m.stats.error.p90};
        return out;
    };
    const auto forward = rows(json["methods"]);
    nlohmann::json shuffled = json["methods"];
    std::mt19937 rng(49);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const auto other = rows(shuffled);
    ASSERT_EQ(forward.size(), other.size());
    for (const auto& [label, stats] : forward) {
        ASSERT_TRUE(other.count(label)) << label;
        EXPECT_EQ(other.at(label), stats) << label;
    }
}

// A shader entry's own fields come from one table (methods/shader/shader_fields.cpp) that
// reads each and writes it into the study's identity: every key it reads is named in
// docs/methods.md, and a key it does not know is refused by name, with the nearest one.
TEST(ShaderFields, EveryKeyIsDocumentedAndAnUnknownOneIsRefused) {
    const std::string path = test::testSourceDir() + "/../docs/methods.md";
    const std::string text = readTextFile(path, path, "", "the documentation", 1 << 22);
    const std::vector<std::string> keys = shaderEntryKeys();
    EXPECT_GE(keys.size(), 20u);
    for (const std::string& key : keys)
        EXPECT_NE(text.find("\"" + key + "\""), std::string::npos)
            << key << " is not in methods.md";
    try {
        parseMethod(nlohmann::json{{"name", "a"}, {"body", "return uv;"}, {"unifroms", 1}},
                    "scene.json", "methods[0]");
        ADD_FAILURE() << "an unknown key was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unifroms"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("uniforms"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace pgt
