// Benchmarks: truth build per geometry and map size, truth frame
// tracing, and each method's cost per fragment at its default parameters.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "frame/render.h"
#include "heightfield/heightfield.h"
#include "mesh/gltf_mesh.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "methods/shader/glsl_method.h"
#include "methods/shader/hlsl.h"
#include "scene/scene.h"
#include "truth/truth.h"

namespace {

using namespace pgt;

Texture smooth(int n) {
    Texture t;
    t.width = t.height = n;
    t.texels.resize(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            t.texel(i, j) = float(0.5 + 0.35 * std::sin(2 * kPi * (i + 0.5) / n) *
                                            std::sin(4 * kPi * (j + 0.5) / n));
    return t;
}

// Tessellation (OpenSubdiv Bfr + height samples) of a map of side range(0) at rate 1.
void BM_TessellatePlane(benchmark::State& state) {
    Texture t = smooth(int(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(tessellatePlane(t, PlaneBase{}, 1));
    state.SetLabel(std::to_string(state.range(0) + 1) + "^2 vertices");
}
BENCHMARK(BM_TessellatePlane)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);

// Displacement + Embree build of an existing tessellation: grid (0) vs triangles (1).
void BM_TruthBuild(benchmark::State& state) {
    Texture t = smooth(int(state.range(0)));
    auto base = tessellatePlane(t, PlaneBase{}, 1);
    TruthGeometry g = state.range(1) ? TruthGeometry::Triangles : TruthGeometry::Grid;
    for (auto _ : state) TruthSurface surface(base, Displacement{0.05, -0.025}, g, false);
    state.SetLabel(std::string(state.range(1) ? "triangles, " : "grid, ") +
                   std::to_string(state.range(0) + 1) + "^2 vertices");
}
BENCHMARK(BM_TruthBuild)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Args({2048, 0})
    ->Unit(benchmark::kMillisecond);

Scene frameScene(int mapSide, int pixels) {
    Scene s;
    s.height = smooth(mapSide);
    s.camera.theta = 60;
    s.camera.phi = 20;
    s.camera.frame = Framing::Fill;
    s.camera.fillSize = 0.5;
    s.camera.width = s.camera.height = pixels;
    return s;
}

// One truth frame of range(0)^2 primary rays at theta 60 over a 1024^2 grid sheet (all
// cores), Embree fed one ray at a time (range(1) = 0) or tile streams (1). The counters
// compare it with the bare loop over the same rays and the same Embree call:
// ratio = frame / bare (target: <= 1.3, docs/performance.md).
void BM_TruthFrame(benchmark::State& state) {
    Scene s = frameScene(1024, int(state.range(0)));
    TruthGeometry g = state.range(2) ? TruthGeometry::Triangles : TruthGeometry::Grid;
    TruthSurface surface(s.height, *s.plane(), s.displacement, 1, g);
    Camera cam = makeCamera(s);
    TraceMode mode = state.range(1) ? TraceMode::Coherent : TraceMode::Single;
    Image2D<TruthSample> frame;  // reused, as the bare loop reuses its ray buffer
    for (auto _ : state) surface.traceFrame(cam, frame, mode);
    double frameMs = 0;
    std::vector<double> t;
    for (int k = 0; k < 5; ++k) {
        auto t0 = std::chrono::steady_clock::now();
        surface.traceFrame(cam, frame, mode);
        t.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count());
    }
    std::sort(t.begin(), t.end());
    frameMs = t[2];
    BareLoopTiming bare = surface.timeBareEmbreeLoop(cam, mode, 5);
    state.counters["frame_ms"] = frameMs;
    state.counters["bare_ms"] = bare.bareMs;
    state.counters["ratio"] = frameMs / bare.bareMs;
    state.counters["Mrays_per_s"] = double(bare.rays) / frameMs / 1e3;
    state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
    state.SetLabel(std::string(state.range(2) ? "triangles, " : "grid, ") +
                   (state.range(1) ? "coherent (rtcIntersect1M tiles)" : "single (rtcIntersect1)"));
}
BENCHMARK(BM_TruthFrame)
    ->Args({512, 0, 0})
    ->Args({512, 1, 0})
    ->Args({1024, 1, 0})
    ->Args({512, 1, 1})
    ->Unit(benchmark::kMillisecond);

// The default study's surface: infinite plane (periodic tile walk), 512^2 at theta 60.
void BM_TruthFramePeriodic(benchmark::State& state) {
    Scene s = frameScene(256, 512);
    s.plane()->infinite = true;
    auto base = tessellatePlane(s.height, *s.plane(), 4);
    TruthSurface surface(base, s.displacement, TruthGeometry::Grid, true);
    Camera cam = makeCamera(s);
    TraceMode mode = state.range(0) ? TraceMode::Coherent : TraceMode::Single;
    for (auto _ : state) benchmark::DoNotOptimize(surface.traceFrame(cam, mode));
    state.SetItemsProcessed(state.iterations() * 512 * 512);
    state.SetLabel(state.range(0) ? "coherent" : "single");
}
BENCHMARK(BM_TruthFramePeriodic)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The shadow rays' cost (docs/model.md §5b): the default study's bricks on the infinite plane,
// 512^2 at view theta range(0), traced without a light (range(1) = 0) and with one at
// theta 45, phi 120 (1): each hit's shadow ray walks the tiles toward the light.
void BM_TruthShadowRays(benchmark::State& state) {
    Scene s = frameScene(256, 512);
    s.height = makeProceduralHeight(
        nlohmann::json::parse(R"({"procedural": "bricks", "size": [256, 256], "bricks": [4, 8],
            "mortar": 0.12, "bevel": 0.2, "jitter": 0.3, "seed": 7})"),
        "bench", "heightmap");
    s.plane()->infinite = true;
    s.camera.theta = double(state.range(0));
    s.camera.fillSize = 1.0;
    if (state.range(1)) s.light = LightSpec{45, 120};
    auto base = tessellatePlane(s.height, *s.plane(), 4);
    TruthSurface surface(base, s.displacement, TruthGeometry::Grid, true);
    Camera cam = makeCamera(s);
    Image2D<TruthSample> frame;
    const std::optional<Vec3d> light = lightToward(s.view());
    for (auto _ : state) surface.traceFrame(cam, frame, TraceMode::Coherent, light);
    state.SetItemsProcessed(state.iterations() * 512 * 512);
    state.SetLabel(state.range(1) ? "with shadow rays" : "primary rays only");
}
BENCHMARK(BM_TruthShadowRays)->ArgsProduct({{30, 60, 80}, {0, 1}})->Unit(benchmark::kMillisecond);

// A (s, b) change on an existing surface (1025^2 vertices): displace + rebuild (0) or
// refit (1), for the grid (range(0) = 0) and the triangle (1) geometry.
void BM_TruthUpdate(benchmark::State& state) {
    Texture t = smooth(1024);
    auto base = tessellatePlane(t, PlaneBase{}, 1);
    TruthGeometry g = state.range(0) ? TruthGeometry::Triangles : TruthGeometry::Grid;
    TruthUpdate u = state.range(1) ? TruthUpdate::Refit : TruthUpdate::Rebuild;
    TruthSurface surface(base, Displacement{0.05, -0.025}, g, false);
    double scale = 0.05;
    for (auto _ : state) {
        scale = scale == 0.05 ? 0.1 : 0.05;
        surface.setDisplacement(Displacement{scale, -scale / 2}, u);
    }
    state.SetLabel(std::string(state.range(0) ? "triangles" : "grid") +
                   (state.range(1) ? " refit" : " rebuild"));
}
BENCHMARK(BM_TruthUpdate)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond);

// Each method alone, single-threaded, over 65,536 fragments at theta 60 (ns per fragment =
// time per iteration / 65,536; items/s is fragments per second).
void BM_Method(benchmark::State& state, const char* json) {
    static Texture t = smooth(256);
    MethodConfig cfg = parseMethod(nlohmann::json::parse(json), "bench", "method");
    MethodTextureCache cache(t, 1.0);
    const MethodTextures& tex = cache.get(cfg, {0.05, -0.025});
    std::vector<Vec2f> uv0(65536);
    Vec3f v(viewFromAngles(60, 20));
    for (size_t k = 0; k < uv0.size(); ++k)
        uv0[k] = Vec2f(float((double(k % 256) + 0.5) / 256), float((double(k / 256) + 0.5) / 256));
    for (auto _ : state) {
        float acc = 0;
        for (const Vec2f& p : uv0) {
            MethodContext<float> c = makeMethodContext<float>(tex);
            Vec2f r = runMethod<float>(*cfg.builtin(), c, p, v);
            acc += r.x + r.y;
        }
        benchmark::DoNotOptimize(acc);
    }
    state.SetItemsProcessed(state.iterations() * int64_t(uv0.size()));
}
BENCHMARK_CAPTURE(BM_Method, none, R"({"name":"none"})");
BENCHMARK_CAPTURE(BM_Method, parallax, R"({"name":"parallax"})");
BENCHMARK_CAPTURE(BM_Method, offset_limited, R"({"name":"offset_limited"})");
BENCHMARK_CAPTURE(BM_Method, steep_8_32, R"({"name":"steep"})");
BENCHMARK_CAPTURE(BM_Method, pom_8_32, R"({"name":"pom"})");
BENCHMARK_CAPTURE(BM_Method, relief_10_5, R"({"name":"relief"})");
BENCHMARK_CAPTURE(BM_Method, iterative_4, R"({"name":"iterative"})");
BENCHMARK_CAPTURE(BM_Method, tangent_plane, R"({"name":"tangent_plane"})");
BENCHMARK_CAPTURE(BM_Method, secant_10_3, R"({"name":"secant"})");
BENCHMARK_CAPTURE(BM_Method, contact_16, R"({"name":"contact"})");
BENCHMARK_CAPTURE(BM_Method, maxmip, R"({"name":"maxmip"})");
BENCHMARK_CAPTURE(BM_Method, cone_32_5, R"({"name":"cone"})");
BENCHMARK_CAPTURE(BM_Method, relaxed_cone_15_6, R"({"name":"relaxed_cone"})");

// maxmip's precomputation: the minimum-maximum pyramid of a range(0)^2 map (one thread).
void BM_MinMaxPyramid(benchmark::State& state) {
    Texture t = smooth(int(state.range(0)));
    for (auto _ : state) {
        MinMaxPyramid p = buildMinMaxPyramid(t);
        benchmark::DoNotOptimize(p.levels.data());
    }
}
BENCHMARK(BM_MinMaxPyramid)->Arg(256)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond);

// cone's precomputation: the conservative cone map of a range(0)^2 brick map (the default
// scene's, scaled), on every core (TBB); with range(1) = 1 relaxed_cone's
// relaxed map built from it (the cone map's own time not included).
void BM_ConeMap(benchmark::State& state) {
    const int n = int(state.range(0));
    Texture t = makeProceduralHeight(
        nlohmann::json::parse(R"({"procedural": "bricks", "size": [)" + std::to_string(n) + "," +
                              std::to_string(n) +
                              R"(], "bricks": [4, 8], "mortar": 0.12, "bevel": 0.2,
                              "jitter": 0.3, "seed": 7})"),
        "bench", "heightmap");
    const ConeMap cone = buildConeMap(t, false);
    for (auto _ : state) {
        if (state.range(1)) {
            ConeMap m = buildRelaxedConeMap(t, cone);
            benchmark::DoNotOptimize(m.ratio.data());
        } else {
            ConeMap m = buildConeMap(t, false);
            benchmark::DoNotOptimize(m.ratio.data());
        }
    }
    state.SetLabel(state.range(1) ? "relaxed (from the cone map)" : "conservative");
}
BENCHMARK(BM_ConeMap)
    ->Args({256, 0})
    ->Args({1024, 0})
    ->Args({256, 1})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A GLSL preset's draw through the GL path (upload, draw, read back) over range(0)
// fragments at theta 60: the per-draw overhead shows as the gap between small and large
// draws' time per fragment.
void BM_GlslDraw(benchmark::State& state) {
    static Texture t = smooth(256);
    MethodConfig cfg = parseMethod(nlohmann::json::parse(R"({"preset":"godot"})"), "bench", "m");
    const size_t n = size_t(state.range(0));
    std::vector<Vec2f> uv0(n);
    std::vector<Vec3f> view(n, Vec3f(viewFromAngles(60, 20)));
    for (size_t k = 0; k < n; ++k)
        uv0[k] =
            Vec2f(float((double(k % 256) + 0.5) / 256), float((double(k / 256 % 256) + 0.5) / 256));
    GlMapUploads maps;
    for (auto _ : state) {
        GlslRun run = runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.05, uv0, view,
                              int(state.range(1)), &maps);
        benchmark::DoNotOptimize(run.uv.data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(n));
}
BENCHMARK(BM_GlslDraw)
    ->Args({512, 0})
    ->Args({9216, 0})
    ->Args({9216, 3})
    ->Args({147456, 0})
    ->Unit(benchmark::kMillisecond);

// An HLSL method's way to the GL (methods/shader/hlsl.h): glslang's HLSL front end with
// legalisation to SPIR-V, then SPIRV-Cross to GLSL 4.50, without the GL's own compile (range(0): 0
// = pgt's pom as HLSL, 1 = the engine-style POM with its #include and a call).
void BM_HlslToGlsl(benchmark::State& state) {
    const std::string data = std::string(PGT_TEST_SOURCE_DIR) + "/data/";
    const nlohmann::json entry =
        state.range(0) == 0
            ? nlohmann::json{{"name", "h"},
                             {"hlsl", data + "hlsl/pom_twin.hlsl"},
                             {"function", "ParallaxOcclusion"}}
            : nlohmann::json{{"name", "h"},
                             {"hlsl", data + "../../scenes/own_shader/engine_pom.hlsl"},
                             {"call", "uv + ParallaxOcclusionOffset(-V, s, b, uv)"}};
    const MethodConfig cfg = parseMethod(entry, "bench", "m");
    for (auto _ : state) {
        std::string glsl = gl::hlslToGlsl(*cfg.shader());
        benchmark::DoNotOptimize(glsl.data());
    }
}
BENCHMARK(BM_HlslToGlsl)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Reading a glTF primitive (mesh/gltf_mesh.h): tinygltf's parse, every check, the node
// transform and the frames. range(0): 0 = the bundled torus (243 vertices, Blender's
// TANGENT), 1 = assimp-testmodels' ClearCoatTest mesh 0 (1,113 vertices, 2,060 triangles, no
// TANGENT: MikkTSpace), 2 = its 2CylinderEngine.glb (1.8 MB, the largest; read and checked
// until it is refused for having no TEXCOORD_0).
void BM_GltfLoad(benchmark::State& state) {
    const std::string models = "/usr/share/assimp/models/glTF2/";
    const std::string file =
        state.range(0) == 0   ? std::string(PGT_TEST_SOURCE_DIR) + "/data/gltf/torus_mirrored.gltf"
        : state.range(0) == 1 ? models + "ClearCoat-glTF/ClearCoatTest.gltf"
                              : models + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    if (!std::filesystem::exists(file)) {
        state.SkipWithError("assimp-testmodels is not installed");
        return;
    }
    for (auto _ : state) {
        try {
            GltfMesh m = loadGltfMesh(file, {}, MeshFrames::Asset, "bench", "base.file");
            benchmark::DoNotOptimize(m.drawn.mesh.vertices.data());
        } catch (const InputError&) {
        }
    }
}
BENCHMARK(BM_GltfLoad)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
