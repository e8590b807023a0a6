// The engine's vertex stage as it ships (docs/methods.md "The engine's vertex stage"): a
// Vulkan-style vertex file run on the base mesh's vertices, its outputs reaching the fragment
// code's inputs by location. Held to a closed form (on a plane, V from the tangent-space
// positions it interpolates is the per-pixel V) and to the defect it exists to show (a
// bitangent cross(N, T) that ignores the tangent's w turns the offsets round on a mirrored
// mesh's mirrored half). Runs in Mesa llvmpipe like tests/gl_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/json_read.h"
#include "frame/render.h"
#include "io/csv_table.h"
#include "methods/config.h"
#include "scene/scene.h"
#include "study/sweep.h"
#include "test_util.h"

namespace pgt {
namespace {

std::string data(const std::string& rel) { return test::testDataDir() + "/" + rel; }

// tests/data/glsl/tangent_space.{vert,frag} with the bitangent's `handedness` 0 (as public
// samples ship: w ignored) or 1.
// The pair's matrices and uniforms, named alike in its GLSL and HLSL files.
nlohmann::json withTangentSpaceBindings(nlohmann::json entry, double handedness) {
    entry["sampler"] = "heightMap";
    entry["matrices"] = {{"ubo.projection", "projection"},
                         {"ubo.view", "view"},
                         {"ubo.model", "model"},
                         {"ubo.cameraPos", "camera_position"}};
    entry["uniforms"] = {{"params.heightScale", "scale"},
                         {"params.heightBias", "bias"},
                         {"options.handedness", handedness}};
    return entry;
}

nlohmann::json vertexEntry(const std::string& name, double handedness) {
    return withTangentSpaceBindings(
        {{"name", name},
         {"glsl", data("glsl/tangent_space.frag")},
         {"vertex", data("glsl/tangent_space.vert")},
         {"api", "d3d"},
         {"call", "offsetParallax(inUV, normalize(inTangentViewPos - inTangentFragPos))"}},
        handedness);
}

// pgt's own parallax fed the per-pixel V of the base's frame.
nlohmann::json perPixelEntry() {
    return {{"name", "pixel_v"},
            {"glsl", "pgt:parallax.glsl"},
            {"sampler", "heightMap"},
            {"call", "ParallaxMapping(uv, V)"},
            {"uniforms", {{"height_scale", "scale"}, {"height_bias", "bias"}}}};
}

RenderResult render(const std::string& base, const std::string& camera,
                    const nlohmann::json& methods, int timingRepeats = 0) {
    const auto dir = test::tempDir("vertex_stage");
    const Scene s = parseScene(
        nlohmann::json::parse(R"({"heightmap": {"procedural": "sine", "size": [64, 64]},
            "address": "repeat", "displacement": {"scale": 0.05, "bias": -0.025},
            "base": )" + base +
                              R"(, "camera": )" + camera +
                              R"(, "truth": {"rate": 1, "uncertainty": false}, "methods": )" +
                              methods.dump() + "}"),
        (dir / "s.json").string());
    RenderResult r = renderFrame(s, {.timingRepeats = timingRepeats});
    std::filesystem::remove_all(dir);
    return r;
}

// On a plane every vertex has one frame, so the tangent-space eye and point it interpolates
// give, per pixel, exactly the per-pixel V (float noise) under a pinhole camera; the
// push-constant and uniform blocks of both stages are set by member. (Under an orthographic
// camera a V taken from a camera position is a perspective from that point, in pgt as in an
// engine: docs/methods.md.)
TEST(VertexStage, OnAPlaneItsVIsThePerPixelV) {
    for (const char* camera :
         {R"({"type": "pinhole", "eye": [0.3, -0.9, 0.7], "target": [0, 0, 0],
              "up": [0, 0, 1], "fov": 50, "resolution": [64, 64]})",
          R"({"type": "pinhole", "eye": [-0.8, 0.2, 0.4], "target": [0.1, 0, 0],
              "up": [0, 0, 1], "fov": 70, "resolution": [63, 49]})"}) {
        const RenderResult r =
            render(R"({"type": "plane"})", camera, {perPixelEntry(), vertexEntry("vertex_w", 1)});
        ASSERT_EQ(r.methods.size(), 2u);
        double worst = 0;
        int n = 0;
        const auto& a = r.methods[0].pixels.data;
        const auto& b = r.methods[1].pixels.data;
        for (size_t k = 0; k < a.size(); ++k)
            if (a[k].covered && b[k].covered)
                worst = std::max(worst, glm::length(a[k].uv - b[k].uv) * 64), ++n;
        std::printf("vertex stage against per-pixel V: %d pixels, worst %.2e texel\n", n, worst);
        EXPECT_GT(n, 1000);
        EXPECT_LT(worst, 1e-4);
    }
}

// A GL-style pair: an interface block between the stages (`out VS_OUT {...} vs_out;` read as
// `fs_in`), a bitangent attribute, plain matrix uniforms bound by convention-free names, a
// depth map. On a plane its uv' is pgt's parallax with the per-pixel V on the depth map's
// surface (s, b) = (k, -k), k its heightScale.
TEST(VertexStage, InterfaceBlocksAndABitangentAttribute) {
    nlohmann::json block = {{"name", "block"},
                            {"glsl", data("glsl/interface_block.frag")},
                            {"vertex", data("glsl/interface_block.vert")},
                            {"sampler", "depthMap"},
                            {"texture", "depth"},
                            {"call",
                             "ParallaxMapping(fs_in.TexCoords, normalize(fs_in.TangentViewPos - "
                             "fs_in.TangentFragPos))"},
                            {"matrices",
                             {{"projection", "projection"},
                              {"view", "view"},
                              {"model", "model"},
                              {"viewPos", "camera_position"}}},
                            {"uniforms", {{"heightScale", "scale"}}},
                            {"scale", 0.05},
                            {"bias", -0.05}};
    nlohmann::json pixel = perPixelEntry();
    pixel["scale"] = 0.05, pixel["bias"] = -0.05;
    const RenderResult r = render(R"({"type": "plane"})",
                                  R"({"type": "pinhole", "eye": [0.3, -0.9, 0.7], "target":
                                      [0, 0, 0], "up": [0, 0, 1], "fov": 50,
                                      "resolution": [64, 64]})",
                                  {pixel, block});
    ASSERT_EQ(r.methods.size(), 2u);
    double worst = 0;
    int n = 0;
    for (size_t k = 0; k < r.methods[0].pixels.data.size(); ++k) {
        const MethodPixel& a = r.methods[0].pixels.data[k];
        const MethodPixel& b = r.methods[1].pixels.data[k];
        if (a.covered && b.covered) worst = std::max(worst, glm::length(a.uv - b.uv) * 64), ++n;
    }
    std::printf("interface-block pair against per-pixel V: %d pixels, worst %.2e texel\n", n,
                worst);
    EXPECT_GT(n, 1000);
    EXPECT_LT(worst, 1e-4);
}

// Blender's glTF torus with mirrored UVs (its own tangents, w -1 on the mirrored half): the
// vertex file as it ships (w ignored) and with w agree where w is +1 and part where it is -1,
// where ignoring w costs about twice the error.
TEST(VertexStage, IgnoringTheTangentsWFailsOnTheMirroredHalf) {
    const RenderResult r =
        render(R"({"type": "gltf", "file": ")" + data("gltf/torus_mirrored.gltf") +
                   R"(", "frames": "asset"})",
               R"({"type": "pinhole", "eye": [0.2, -1.3, 0.9], "target": [0, 0, 0], "up": [0, 0, 1],
            "fov": 45, "resolution": [128, 128]})",
               {vertexEntry("shipped", 0), vertexEntry("with_w", 1)});
    ASSERT_EQ(r.methods.size(), 2u);
    const auto& shipped = r.methods[0];
    const auto& withW = r.methods[1];
    int same = 0, apart = 0;
    double errShipped = 0, errWithW = 0;
    for (size_t k = 0; k < shipped.pixels.data.size(); ++k) {
        if (!shipped.pixels.data[k].covered || !withW.pixels.data[k].covered ||
            !std::isfinite(shipped.errTexels.data[k]) || !std::isfinite(withW.errTexels.data[k]))
            continue;
        if (shipped.pixels.data[k].uv == withW.pixels.data[k].uv) {
            ++same;
            continue;
        }
        ++apart;
        errShipped += shipped.errTexels.data[k];
        errWithW += withW.errTexels.data[k];
    }
    std::printf("%d pixels alike, %d apart: mean error there %.3f (w ignored) vs %.3f texels\n",
                same, apart, errShipped / apart, errWithW / apart);
    EXPECT_GT(same, 1000);
    EXPECT_GT(apart, 1000);
    EXPECT_GT(errShipped, 1.5 * errWithW);  // measured 1.95x
}

const char* kPlaneCamera = R"({"type": "pinhole", "eye": [0.3, -0.9, 0.7], "target": [0, 0, 0],
    "up": [0, 0, 1], "fov": 50, "resolution": [64, 64]})";

// The vertex file's #include lines expanded as the fragment file's are: the same stage split
// over two files gives the same uv' to the bit, and an error in the include names its file
// and line.
TEST(VertexStage, ItsIncludesAreExpanded) {
    const auto dir = test::tempDir("vertex_stage_include");
    std::string whole = readTextFile(data("glsl/tangent_space.vert"), "", "", "test", 1 << 20);
    std::ofstream(dir / "part.glsl") << whole.substr(whole.find('\n') + 1);
    std::ofstream(dir / "split.vert") << "#version 450\n#include \"part.glsl\"\n";
    std::ofstream(dir / "bad.glsl") << "// broken\nvec3 broken = ;\n";
    std::ofstream(dir / "broken.vert") << "#version 450\n#include \"bad.glsl\"\n"
                                       << whole.substr(whole.find('\n') + 1);
    nlohmann::json split = vertexEntry("split", 1);
    split["vertex"] = (dir / "split.vert").string();
    const RenderResult r =
        render(R"({"type": "plane"})", kPlaneCamera, {vertexEntry("whole", 1), split});
    ASSERT_EQ(r.methods.size(), 2u);
    int n = 0;
    for (size_t k = 0; k < r.methods[0].pixels.data.size(); ++k)
        if (r.methods[0].pixels.data[k].covered) {
            EXPECT_EQ(r.methods[0].pixels.data[k].uv, r.methods[1].pixels.data[k].uv);
            ++n;
        }
    EXPECT_GT(n, 1000);
    nlohmann::json broken = vertexEntry("broken", 1);
    broken["vertex"] = (dir / "broken.vert").string();
    try {
        render(R"({"type": "plane"})", kPlaneCamera, nlohmann::json::array({broken}));
        ADD_FAILURE() << "a broken include compiled";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.glsl:2"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

// Timed like any GL method: on the frame's timing subset (the outputs read at its fragments'
// barycentrics) and once per view in a study.
TEST(VertexStage, ItIsTimedInAFrameAndInAStudy) {
    const RenderResult r = render(R"({"type": "plane"})", kPlaneCamera,
                                  nlohmann::json::array({vertexEntry("vertex_w", 1)}), 1);
    ASSERT_EQ(r.methods.size(), 1u);
    EXPECT_TRUE(std::isfinite(r.methods[0].nsPerPixel) && r.methods[0].nsPerPixel > 0)
        << r.methods[0].nsPerPixel;
    const auto dir = test::tempDir("vertex_stage_study");
    const Scene scene =
        parseScene(nlohmann::json::parse(R"({"heightmap": {"procedural": "sine", "size": [32, 32]},
            "base": {"type": "plane"}, "displacement": {"scale": 0.05, "bias": -0.025},
            "camera": {"type": "orthographic", "theta": 40, "resolution": [32, 32]},
            "truth": {"rate": 1, "uncertainty": false},
            "sweep": {"theta": [30, 50], "timing": {"repeats": 1, "fragments": 256}},
            "methods": )" + nlohmann::json::array({vertexEntry("vertex_w", 1)}).dump() +
                                         "}"),
                   (dir / "s.json").string());
    SweepOptions opt;
    opt.outDir = (dir / "study").string();
    opt.progress = false;
    ASSERT_TRUE(runSweep(scene, parseStudy(scene), opt).finished);
    const std::string text =
        readTextFile((dir / "study" / "results.csv").string(), "", "", "results", 1 << 24);
    const std::vector<std::vector<std::string>> records = splitCsvRecords(text, 0, nullptr);
    ASSERT_FALSE(records.empty());
    const std::vector<std::string>& names = records[0];
    const size_t ns = size_t(std::find(names.begin(), names.end(), "ns_per_px") - names.begin());
    ASSERT_LT(ns, names.size());
    int rows = 0;
    for (size_t i = 1; i < records.size(); ++i, ++rows) {
        ASSERT_LT(ns, records[i].size());
        EXPECT_GT(std::stod(records[i][ns]), 0) << records[i][ns];
    }
    EXPECT_EQ(rows, 2);
    std::filesystem::remove_all(dir);
}

// tests/data/hlsl/tangent_space.{vs,ps}.hlsl, the HLSL twin of vertexEntry's pair: structs
// with semantics, a cbuffer's matrices applied as mul(M, v), the pixel stage's input struct
// read by the call as `input`.
nlohmann::json hlslVertexEntry(const std::string& name, double handedness) {
    return withTangentSpaceBindings(
        {{"name", name},
         {"hlsl", data("hlsl/tangent_space.ps.hlsl")},
         {"vertex", data("hlsl/tangent_space.vs.hlsl")},
         {"call",
          "offsetParallax(input.UV, normalize(input.TangentViewPos - input.TangentFragPos))"}},
        handedness);
}

// The HLSL pair (glslang's HLSL front end, SPIRV-Cross, semantics linking the stages) gives
// the GLSL pair's uv' at every pixel, on the plane and on both halves of the mirrored torus:
// two compilers, one answer, and the defect of the shipped bitangent in HLSL too.
TEST(VertexStage, TheHlslPairIsTheGlslPair) {
    for (const char* base : {R"({"type": "plane"})", "torus"}) {
        const std::string b = std::string(base) == "torus" ? R"({"type": "gltf", "file": ")" +
                                                                 data("gltf/torus_mirrored.gltf") +
                                                                 R"(", "frames": "asset"})"
                                                           : std::string(base);
        const RenderResult r = render(
            b,
            R"({"type": "pinhole", "eye": [0.2, -1.3, 0.9], "target": [0, 0, 0], "up": [0, 0, 1],
                "fov": 45, "resolution": [96, 96]})",
            {vertexEntry("glsl_shipped", 0), hlslVertexEntry("hlsl_shipped", 0),
             vertexEntry("glsl_w", 1), hlslVertexEntry("hlsl_w", 1)});
        ASSERT_EQ(r.methods.size(), 4u);
        for (size_t m : {0u, 2u}) {
            // |uv'(GLSL) - uv'(HLSL)| in texels over (1 + |uv'| in texels): float rounding (the
            // translation fuses h s + b into an fma) grows with the offset where V.z nears 0
            // (measured: 9 grazing pixels of 5763 apart by up to 0.022 texel, on offsets of
            // hundreds of texels; the ratio at most 9.6e-5).
            double worst = 0, worstRatio = 0;
            int n = 0, over = 0;
            for (size_t k = 0; k < r.methods[m].pixels.data.size(); ++k) {
                const MethodPixel& g = r.methods[m].pixels.data[k];
                const MethodPixel& h = r.methods[m + 1].pixels.data[k];
                ASSERT_EQ(g.covered, h.covered);
                if (!g.covered) continue;
                const double d = glm::length(g.uv - h.uv) * 64;
                worst = std::max(worst, d), ++n, over += d > 1e-4;
                worstRatio = std::max(worstRatio, d / (1 + glm::length(g.uv) * 64));
            }
            std::printf(
                "%s, %s: HLSL against GLSL on %d pixels: worst %.2e texel, %d over "
                "1e-4, worst ratio to the offset %.2e\n",
                base, r.methods[m].config.label.c_str(), n, worst, over, worstRatio);
            EXPECT_GT(n, 1000);
            EXPECT_LT(worstRatio, 1e-3);
            EXPECT_LE(over, n / 100);
        }
    }
}

// The matrices' orientation: the eye-space position, from the view matrix, handed to the
// fragment code as uv' by a GLSL pair (view * p), an HLSL pair (mul(view, p)) and an HLSL pair
// written for row vectors (mul(p, view), "vectors": "row") is one value, also where the HLSL
// vertex entry hands its outputs through `out` parameters and the pixel stage takes them as
// parameters ("stage_input"); the row-vector file read as column vectors is not.
TEST(VertexStage, MatricesApplyAsEachLanguageMultiplies) {
    const auto dir = test::tempDir("vertex_stage_matrices");
    std::ofstream(dir / "eye.vert") << "#version 450\nin vec3 inPos;\nuniform mat4 view;\n"
                                       "out vec3 vEye;\n"
                                       "void main() { vEye = (view * vec4(inPos, 1.0)).xyz; }\n";
    std::ofstream(dir / "eye.frag") << "#version 450\nin vec3 vEye;\n"
                                       "vec2 F(vec2 uv, vec3 V) { return vEye.xy; }\n";
    for (const char* order :
         {"mul(view, float4(input.Pos, 1.0))", "mul(float4(input.Pos, 1.0), view)"})
        std::ofstream(dir / (order[4] == 'v' ? "col.hlsl" : "row.hlsl"))
            << "struct VIn { float3 Pos : POSITION; };\n"
               "struct VOut { float4 Pos : SV_POSITION; float3 Eye : TEXCOORD0; };\n"
               "float4x4 view;\n"
               "VOut main(VIn input) { VOut o; o.Pos = float4(input.Pos, 1.0); o.Eye = "
            << order << ".xyz; return o; }\n";
    std::ofstream(dir / "eye.hlsl")
        << "struct VOut { float4 Pos : SV_POSITION; float3 Eye : TEXCOORD0; };\n";
    std::ofstream(dir / "params.hlsl")
        << "float4x4 view;\nvoid VS(float3 pos : POSITION, out float4 oPos : SV_Position,\n"
           "        out float3 oEye : TEXCOORD0) {\n    oPos = float4(pos, 1.0);\n"
           "    oEye = mul(view, float4(pos, 1.0)).xyz;\n}\n";
    auto entry = [&](const std::string& name, const std::string& vertex, const char* vectors) {
        nlohmann::json e = {{"name", name},
                            {"vertex", (dir / vertex).string()},
                            {"sampler", ""},
                            {"matrices", {{"view", "view"}}}};
        if (vertex == "eye.vert")
            e["glsl"] = (dir / "eye.frag").string(), e["function"] = "F";
        else
            e["hlsl"] = (dir / "eye.hlsl").string(), e["call"] = "input.Eye.xy";
        if (vectors) e["vectors"] = vectors;
        return e;
    };
    nlohmann::json params = entry("hlsl_out_params", "params.hlsl", nullptr);
    params["vertex_entry"] = "VS", params["stage_input"] = "float3 eye : TEXCOORD0";
    params["call"] = "eye.xy";
    const RenderResult r =
        render(R"({"type": "plane"})", kPlaneCamera,
               {entry("glsl", "eye.vert", nullptr), entry("hlsl", "col.hlsl", nullptr),
                entry("hlsl_row", "row.hlsl", "row"),
                entry("hlsl_row_as_column", "row.hlsl", nullptr), params});
    ASSERT_EQ(r.methods.size(), 5u);
    double worst = 0, apart = 0;
    int n = 0;
    for (size_t k = 0; k < r.methods[0].pixels.data.size(); ++k) {
        if (!r.methods[0].pixels.data[k].covered) continue;
        const Vec2d g = r.methods[0].pixels.data[k].uv;
        ++n;
        worst = std::max({worst, glm::length(g - r.methods[1].pixels.data[k].uv),
                          glm::length(g - r.methods[2].pixels.data[k].uv),
                          glm::length(g - r.methods[4].pixels.data[k].uv)});
        apart = std::max(apart, glm::length(g - r.methods[3].pixels.data[k].uv));
    }
    std::printf(
        "eye-space xy on %d pixels: the four alike within %.2e, the misread file %.3f "
        "away\n",
        n, worst, apart);
    EXPECT_GT(n, 1000);
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(apart, 0.1);
    std::filesystem::remove_all(dir);
}

// Matrix outputs (GLSL `out mat3`, HLSL float3x3): a world-to-tangent matrix and the vector to
// the eye handed on per vertex, V = M (eye - p) per fragment. On a plane the matrix is one
// value and eye - p interpolates exactly, so both pairs give pgt's parallax with the per-pixel
// V (float noise).
TEST(VertexStage, MatrixOutputsReachTheFragmentCode) {
    const auto dir = test::tempDir("vertex_stage_mat3");
    std::ofstream(dir / "m.vert")
        << "#version 450\nin vec3 inPos;\nin vec3 inNormal;\nin vec4 inTangent;\nin vec2 inUV;\n"
           "uniform vec3 camera;\nout mat3 worldToTangent;\nout vec3 toEye;\nout vec2 vUV;\n"
           "void main() {\n    vec3 B = cross(inNormal, inTangent.xyz) * inTangent.w;\n"
           "    worldToTangent = transpose(mat3(inTangent.xyz, B, inNormal));\n"
           "    toEye = camera - inPos;\n    vUV = inUV;\n    gl_Position = vec4(inPos, 1.0);\n}\n";
    std::ofstream(dir / "m.frag")
        << "#version 450\nin mat3 worldToTangent;\nin vec3 toEye;\nin vec2 vUV;\n"
           "uniform sampler2D heightMap;\nuniform float heightScale;\nuniform float heightBias;\n"
           "vec2 F(vec2 uv, vec3 V) {\n    vec3 v = normalize(worldToTangent * toEye);\n"
           "    float h = texture(heightMap, vUV).r * heightScale + heightBias;\n"
           "    return vUV + h * v.xy / v.z;\n}\n";
    std::ofstream(dir / "m.vs.hlsl")
        << "struct VIn { float3 Pos : POSITION; float3 Normal : NORMAL; float4 Tangent : TANGENT;\n"
           "             float2 UV : TEXCOORD0; };\n"
           "struct VOut { float4 Pos : SV_POSITION; float3x3 WorldToTangent : TEXCOORD1;\n"
           "              float3 ToEye : TEXCOORD4; float2 UV : TEXCOORD0; };\n"
           "float3 camera;\n"
           "VOut main(VIn i) {\n    VOut o;\n"
           "    float3 B = cross(i.Normal, i.Tangent.xyz) * i.Tangent.w;\n"
           "    o.WorldToTangent = float3x3(i.Tangent.xyz, B, i.Normal);\n"
           "    o.ToEye = camera - i.Pos;\n    o.UV = i.UV;\n    o.Pos = float4(i.Pos, 1.0);\n"
           "    return o;\n}\n";
    std::ofstream(dir / "m.ps.hlsl")
        << "Texture2D heightMap;\nSamplerState heightSampler;\nfloat heightScale;\n"
           "float heightBias;\n"
           "struct VOut { float4 Pos : SV_POSITION; float3x3 WorldToTangent : TEXCOORD1;\n"
           "              float3 ToEye : TEXCOORD4; float2 UV : TEXCOORD0; };\n"
           "float2 parallax(VOut input) {\n"
           "    float3 v = normalize(mul(input.WorldToTangent, input.ToEye));\n"
           "    float h = heightMap.Sample(heightSampler, input.UV).r * heightScale + heightBias;\n"
           "    return input.UV + h * v.xy / v.z;\n}\n";
    nlohmann::json glsl = {{"name", "glsl_mat3"},
                           {"glsl", (dir / "m.frag").string()},
                           {"vertex", (dir / "m.vert").string()},
                           {"function", "F"},
                           {"sampler", "heightMap"},
                           {"matrices", {{"camera", "camera_position"}}},
                           {"uniforms", {{"heightScale", "scale"}, {"heightBias", "bias"}}}};
    nlohmann::json hlsl = glsl;
    hlsl.erase("glsl"), hlsl.erase("function");
    hlsl["name"] = "hlsl_float3x3", hlsl["hlsl"] = (dir / "m.ps.hlsl").string();
    hlsl["vertex"] = (dir / "m.vs.hlsl").string(), hlsl["call"] = "parallax(input)";
    const RenderResult r =
        render(R"({"type": "plane"})", kPlaneCamera, {perPixelEntry(), glsl, hlsl});
    ASSERT_EQ(r.methods.size(), 3u);
    for (size_t m : {1u, 2u}) {
        double worst = 0;
        int n = 0;
        for (size_t k = 0; k < r.methods[0].pixels.data.size(); ++k) {
            const MethodPixel& a = r.methods[0].pixels.data[k];
            const MethodPixel& b = r.methods[m].pixels.data[k];
            if (a.covered && b.covered) worst = std::max(worst, glm::length(a.uv - b.uv) * 64), ++n;
        }
        std::printf("%s against per-pixel V: %d pixels, worst %.2e texel\n",
                    r.methods[m].config.label.c_str(), n, worst);
        EXPECT_GT(n, 1000);
        EXPECT_LT(worst, 1e-4);
    }
    std::filesystem::remove_all(dir);
}

// An HLSL vertex stage's fields: an entry the file does not define, a pixel input no vertex
// output carries, a field for another language; each an error naming the field.
TEST(VertexStage, HlslFieldsAreChecked) {
    auto message = [](nlohmann::json e) {
        try {
            parseMethod(e, data("hlsl/s.json"), "methods[0]");
        } catch (const InputError& err) {
            return std::string(err.what());
        }
        return std::string("no error");
    };
    nlohmann::json e = hlslVertexEntry("a", 1);
    e["vertex_entry"] = "VSMain";
    EXPECT_NE(message(e).find("vertex_entry"), std::string::npos) << message(e);
    const auto dir = test::tempDir("vertex_stage_hlsl_fields");
    std::ofstream(dir / "p.hlsl") << "struct PIn { float2 UV : TEXCOORD0; float3 Extra : "
                                     "TEXCOORD7; };\n";
    e = hlslVertexEntry("a", 1);
    e["hlsl"] = (dir / "p.hlsl").string();
    e["sampler"] = "";
    e["uniforms"] = nlohmann::json::object();
    e["call"] = "input.UV + input.Extra.xy";
    e["stage_input"] = "PIn input";
    EXPECT_NE(message(e).find("TEXCOORD7"), std::string::npos) << message(e);
    // A tangent under TEXCOORD1 beside the uv's TEXCOORD0 (as a public sample ships it), bound
    // by semantics alone; a nointerpolation output; outputs through parameters of an entry
    // that returns its SV_Position, without "stage_input".
    std::ofstream(dir / "v.hlsl")
        << "struct VIn { float3 P : POSITION; float2 UV : TEXCOORD0; float4 T : TEXCOORD1; };\n"
           "struct VOut { float4 Pos : SV_POSITION; nointerpolation float2 UV : TEXCOORD0; };\n"
           "VOut main(VIn i) { VOut o; o.Pos = float4(i.P + i.T.xyz, 1.0); o.UV = i.UV;\n"
           "    return o; }\n"
           "float4 VS(float3 p : POSITION, out float2 uv : TEXCOORD0) : SV_Position {\n"
           "    uv = p.xy; return float4(p, 1.0); }\n";
    std::ofstream(dir / "q.hlsl") << "struct VOut { float4 Pos : SV_POSITION; nointerpolation "
                                     "float2 UV : TEXCOORD0; };\n";
    e = hlslVertexEntry("a", 1);
    e["hlsl"] = (dir / "q.hlsl").string(), e["vertex"] = (dir / "v.hlsl").string();
    e["sampler"] = "", e["uniforms"] = nlohmann::json::object();
    e["matrices"] = nlohmann::json::object();
    e["call"] = "input.UV";
    EXPECT_NE(message(e).find("TEXCOORD1"), std::string::npos) << message(e);
    e["attributes"] = {{"POSITION", "position"}, {"TEXCOORD0", "uv"}, {"TEXCOORD1", "tangent"}};
    EXPECT_NE(message(e).find("nointerpolation"), std::string::npos) << message(e);
    e["vertex_entry"] = "VS", e.erase("attributes");
    EXPECT_NE(message(e).find("stage_input"), std::string::npos) << message(e);
    // A 300,000-space run where pgt looks for the struct and the textures (a scan that
    // recursed per character overflowed the stack): read, no crash.
    std::ofstream(dir / "long.hlsl")
        << "struct" << std::string(300000, ' ')
        << "VOut { float4 Pos : SV_POSITION; float2 UV : TEXCOORD0; };\nTexture2D"
        << std::string(300000, ' ')
        << "unused;\n"
           "VOut main(float3 p : POSITION, float2 uv : TEXCOORD0) {\n"
           "    VOut o; o.Pos = float4(p, 1.0); o.UV = uv; return o; }\n";
    std::ofstream(dir / "q.hlsl") << "struct VOut { float4 Pos : SV_POSITION; float2 UV : "
                                     "TEXCOORD0; };\n";
    e["vertex"] = (dir / "long.hlsl").string(), e["vertex_entry"] = "main";
    EXPECT_EQ(message(e), "no error");
    std::filesystem::remove_all(dir);
    e = vertexEntry("a", 1);
    e["vertex_entry"] = "main";
    EXPECT_NE(message(e).find("vertex_entry"), std::string::npos) << message(e);
    e = perPixelEntry();
    e["matrices"] = {{"m", "view"}};
    EXPECT_NE(message(e).find("matrices"), std::string::npos) << message(e);
}

// A fragment input no vertex output feeds, an attribute pgt cannot guess, a matrix name pgt
// has not: each an error naming the field.
TEST(VertexStage, FieldsAreChecked) {
    const auto dir = test::tempDir("vertex_stage_fields");
    std::ofstream(dir / "v.vert") << "#version 450\nlayout(location = 0) in vec3 inPos;\n"
                                     "layout(location = 0) out vec2 outUV;\n"
                                     "void main() { outUV = inPos.xy; }\n";
    std::ofstream(dir / "w.vert") << "#version 450\nin vec3 corner;\nout vec2 vUV;\n"
                                     "void main() { vUV = corner.xy; }\n";
    std::ofstream(dir / "f.frag") << "#version 450\nlayout(location = 1) in vec2 inUV;\n"
                                     "vec2 F(vec2 uv, vec3 V) { return inUV; }\n";
    auto parse = [&](nlohmann::json e) {
        e["glsl"] = "f.frag", e["function"] = "F", e["sampler"] = "";
        return parseMethod(e, (dir / "s.json").string(), "methods[0]");
    };
    auto message = [&](const nlohmann::json& e) {
        try {
            parse(e);
        } catch (const InputError& err) {
            return std::string(err.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message({{"name", "a"}, {"vertex", "v.vert"}}).find("location 1"), std::string::npos);
    EXPECT_NE(message({{"name", "a"}, {"vertex", "w.vert"}}).find("corner"), std::string::npos);
    EXPECT_NE(message({{"name", "a"}, {"vertex", "v.vert"}, {"attributes", {{"inPos", "place"}}}})
                  .find("attributes.inPos"),
              std::string::npos);
    // What pgt would hand on wrongly: a flat output, an array input.
    std::ofstream(dir / "flat.vert") << "#version 450\nin vec3 inPos;\nflat out vec2 vUV;\n"
                                        "void main() { vUV = inPos.xy; }\n";
    std::ofstream(dir / "f.frag") << "#version 450\nflat in vec2 vUV;\n"
                                     "vec2 F(vec2 uv, vec3 V) { return vUV; }\n";
    EXPECT_NE(message({{"name", "a"}, {"vertex", "flat.vert"}}).find("flat"), std::string::npos);
    std::ofstream(dir / "f.frag") << "#version 450\nin vec2 vUV[2];\n"
                                     "vec2 F(vec2 uv, vec3 V) { return vUV[1]; }\n";
    EXPECT_NE(message({{"name", "a"}, {"vertex", "flat.vert"}}).find("an array"),
              std::string::npos);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt
