// Benchmarks (issue 6 starts here): truth build per geometry and map size, truth frame
// tracing, and each method's cost per fragment at its default parameters.
#include <benchmark/benchmark.h>

#include <cmath>

#include "methods/registry.h"
#include "scene/scene.h"
#include "study/render.h"
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
    state.SetLabel(state.range(1) ? "triangles" : "grid");
}
BENCHMARK(BM_TruthBuild)->Args({1024, 0})->Args({1024, 1})->Unit(benchmark::kMillisecond);

// One truth frame of 512^2 primary rays at theta 60 over a 1024^2 grid sheet (all cores).
void BM_TruthFrame(benchmark::State& state) {
    Scene s;
    s.height = smooth(1024);
    s.camera.theta = 60;
    s.camera.phi = 20;
    s.camera.frame = "fill";
    s.camera.fillSize = 0.5;
    s.camera.width = s.camera.height = 512;
    TruthSurface surface(s.height, s.plane, s.displacement, 1, TruthGeometry::Grid);
    Camera cam = makeCamera(s);
    for (auto _ : state) benchmark::DoNotOptimize(surface.traceFrame(cam));
    state.SetItemsProcessed(state.iterations() * 512 * 512);
}
BENCHMARK(BM_TruthFrame)->Unit(benchmark::kMillisecond);

// Each method alone, single-threaded, over 65,536 fragments at theta 60 (ns per fragment =
// time per iteration / 65,536; items/s is fragments per second).
void BM_Method(benchmark::State& state, const char* json) {
    static Texture t = smooth(256);
    MethodConfig cfg = parseMethod(nlohmann::json::parse(json), "bench", "method");
    MethodTextures tex = makeMethodTextures(t, 0.05, -0.025, 1.0, needsDerivedMaps(cfg.kind));
    std::vector<Vec2f> uv0(65536);
    Vec3f v(viewFromAngles(60, 20));
    for (size_t k = 0; k < uv0.size(); ++k)
        uv0[k] = Vec2f(float((double(k % 256) + 0.5) / 256), float((double(k / 256) + 0.5) / 256));
    for (auto _ : state) {
        float acc = 0;
        for (const Vec2f& p : uv0) {
            MethodContext<float> c;
            c.height = tex.height;
            if (tex.derived) c.normal = &tex.derived->normal, c.parallax = &tex.derived->parallax;
            c.scale = 0.05f;
            c.bias = -0.025f;
            Vec2f r = runMethod<float>(cfg, c, p, v);
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

}  // namespace

BENCHMARK_MAIN();
