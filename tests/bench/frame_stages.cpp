// The frame's stages against their floors (docs/performance.md "A frame's stages against their
// floors"): `pgt render` of the default scene cut to none, parallax and pom without a light,
// on the finite plane (so that every pixel's ray is one Embree ray), at range(0)^2 pixels,
// each stage's wall time from the pipeline's own clocks; and beside it what each stage cannot
// go below on this machine: Embree alone on the same rays (both rates), a minimal rasteriser
// of the same two triangles (perspective-correct uv per pixel, nothing else), each method's
// own kernel over the frame's fragments on all cores, and memory bandwidth.
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/clock.h"
#include "evaluate/evaluate.h"
#include "frame/render.h"
#include "methods/config.h"
#include "raster/fragment_list.h"
#include "scene/scene.h"
#include "study/outputs.h"
#include "truth/builder.h"
#include "truth/truth.h"

namespace {

using namespace pgt;

Scene stageScene(int pixels) {
    Scene s = loadScene(std::string(PGT_SCENE_DIR) + "/default.json");
    s.light.reset();
    s.plane()->infinite = false;
    s.camera.width = s.camera.height = pixels;
    s.methods = parseMethods(
        nlohmann::json::parse(
            R"(["none", "parallax", {"name": "pom", "min_layers": 8, "max_layers": 32}])"),
        "bench", "methods");
    return s;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The frame as `pgt render --no-timing` makes it, its files written to a temporary folder.
void BM_FrameStages(benchmark::State& state) {
    const Scene s = stageScene(int(state.range(0)));
    const auto dir = std::filesystem::temp_directory_path() / "pgt_bench_stages";
    std::map<std::string, std::vector<double>> ms;
    for (auto _ : state) {
        std::filesystem::remove_all(dir);
        auto t0 = Clock::now();
        RenderWriter writer(s, dir.string(), s.camera.width, s.camera.height, s.methods);
        RenderOptions opt{.timingRepeats = 0};
        opt.frame = {.keepImages = false, .sinks = {&writer}, .keepCodedErrors = true};
        RenderResult r = renderFrame(s, opt);
        auto t1 = Clock::now();
        writer.finish(r);
        ms["maps_and_summary"].push_back(msSince(t1));
        ms["whole"].push_back(msSince(t0));
        for (const auto& [stage, t] : r.timings.byName()) ms[stage].push_back(t);
    }
    std::filesystem::remove_all(dir);
    for (const auto& [stage, t] : ms) state.counters[stage + "_ms"] = median(t);
    state.SetLabel("default scene, none + parallax + pom, no light, finite plane");
}
BENCHMARK(BM_FrameStages)->Arg(512)->Arg(2048)->Iterations(3)->Unit(benchmark::kMillisecond);

// The raster stage on its own, as the pipeline runs it for this frame (the Rasterizer set up
// once, then each band rasterised and compacted; no light, no GL method, so no light vectors
// and no helper lanes), with nothing else on the cores: in BM_FrameStages the previous band's
// frame.exr is encoded beside it.
void BM_RasterStage(benchmark::State& state) {
    const Scene s = stageScene(int(state.range(0)));
    const Camera cam = makeCamera(s);
    const BaseMesh mesh = drawnBaseMesh(s.base, cam);
    const RasterOptions o = rasterOptions(s, s.view(), s.methods);
    Image2D<Fragment> frags;
    Image2D<FragmentInputs> inputs;
    std::vector<HelperLane> helpers;
    FragmentList list;
    const int H = cam.height(), rows = bandRows(cam.width());
    for (auto _ : state) {
        const Rasterizer raster(mesh, cam, o);
        RasterStats stats;
        for (int y0 = 0; y0 < H; y0 += rows) {
            raster.rasterizeRows(y0, std::min(H, y0 + rows), frags, stats, &inputs, &helpers);
            compactFragments(frags, &inputs, o, list, nullptr);
        }
        benchmark::DoNotOptimize(list.pixel.data());
    }
    state.SetLabel("the frame of BM_FrameStages");
}
BENCHMARK(BM_RasterStage)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond);

// A minimal rasteriser of the drawn mesh's triangles: edge functions over each triangle's
// bounding box, perspective-correct uv into a float image (the floor of the raster stage,
// which also gives V in its frame, uv's derivatives and the fragment list).
double minimalRasterMs(const BaseMesh& mesh, const Camera& cam, std::vector<Vec2f>& uv) {
    const int W = cam.width(), H = cam.height();
    uv.assign(size_t(W) * H, Vec2f(NAN));
    auto t0 = Clock::now();
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        Vec2d p[3];
        double iw[3];
        Vec2d tuv[3];
        for (int k = 0; k < 3; ++k) {
            const BaseVertex& v = mesh.vertices[mesh.indices[i + size_t(k)]];
            const Vec3d c = cam.toCamera(v.position);
            p[k] = cam.toScreen(c);
            iw[k] = cam.isOrthographic() ? 1.0 : 1.0 / c.z;
            tuv[k] = v.uv * iw[k];
        }
        const double area =
            (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
        if (area == 0) continue;
        const int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
        const int x1 = std::min(W - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
        const int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
        const int y1 = std::min(H - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        tbb::parallel_for(y0, y1 + 1, [&](int y) {
            for (int x = x0; x <= x1; ++x) {
                const Vec2d q(x + 0.5, y + 0.5);
                double e[3];
                for (int k = 0; k < 3; ++k) {
                    const Vec2d a = p[(k + 1) % 3], b = p[(k + 2) % 3];
                    e[k] = ((b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x)) / area;
                }
                if (e[0] < 0 || e[1] < 0 || e[2] < 0) continue;
                const double w = e[0] * iw[0] + e[1] * iw[1] + e[2] * iw[2];
                uv[size_t(y) * W + x] = Vec2f((tuv[0] * e[0] + tuv[1] * e[1] + tuv[2] * e[2]) / w);
            }
        });
    }
    return msSince(t0);
}

// Memory bandwidth: GB/s of a 256 MB copy, all cores.
double copyGbPerS() {
    const size_t n = size_t(256) << 20;
    std::vector<char> a(n, 1), b(n, 0);
    std::vector<double> t;
    for (int r = 0; r < 3; ++r) {
        auto t0 = Clock::now();
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, size_t(1) << 22), [&](const auto& rg) {
            std::memcpy(b.data() + rg.begin(), a.data() + rg.begin(), rg.size());
        });
        t.push_back(msSince(t0));
    }
    benchmark::DoNotOptimize(b.data());
    return 2.0 * double(n) / (median(t) * 1e-3) / 1e9;  // read + write
}

// The floors of the same frame.
void BM_FrameFloors(benchmark::State& state) {
    const Scene s = stageScene(int(state.range(0)));
    const Camera cam = makeCamera(s);
    TruthBuilder builder(s);
    builder.limitToView(cam, lightToward(s.view()), s.displacement);
    const TruthPair truths = builder.build(s.displacement, true);
    const BaseMesh mesh = drawnBaseMesh(s.base, cam);
    const RasterOptions o = rasterOptions(s, s.view(), s.methods);
    FragmentList frags;  // as the pipeline makes it
    compactFragments(rasterize(mesh, cam, o), nullptr, o, frags);
    MethodTextureCache textures(s.height, s.uvExtent);
    std::vector<Vec2f> uv;
    std::map<std::string, std::vector<double>> ms;
    for (auto _ : state) {
        ms["embree"].push_back(
            truths.truth->timeBareEmbreeLoop(cam, TraceMode::Coherent, 1).bareMs);
        ms["embree_fine"].push_back(
            truths.fine->timeBareEmbreeLoop(cam, TraceMode::Coherent, 1).bareMs);
        ms["raster"].push_back(minimalRasterMs(mesh, cam, uv));
        for (const MethodConfig& cfg : s.methods) {
            auto t0 = Clock::now();
            benchmark::DoNotOptimize(evaluateMethod(cfg, frags, textures.get(cfg, s.displacement),
                                                    cam.width(), cam.height(), false));
            ms["method_" + cfg.label].push_back(msSince(t0));
        }
    }
    for (const auto& [what, t] : ms) state.counters[what + "_ms"] = median(t);
    state.counters["copy_GB_per_s"] = copyGbPerS();
    state.SetLabel("the same frame's floors");
}
BENCHMARK(BM_FrameFloors)->Arg(512)->Arg(2048)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace
