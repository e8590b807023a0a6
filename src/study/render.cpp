// The frame pipeline: truth -> raster -> methods -> comparison, with stage timings.
#include "study/render.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <random>

#include "core/clock.h"
#include "core/error.h"
#include "core/memory.h"
#include "gl/glsl_method.h"

namespace pgt {

BaseMesh sceneBaseMesh(const Scene& scene, const Camera& camera) {
    if (scene.isMesh) return scene.mesh.drawn->mesh;
    int tiles =
        scene.plane.infinite ? tilesToCover(camera, scene.plane.center, scene.plane.size) : 0;
    return makePlaneMesh(scene.plane.center, scene.plane.size, scene.plane.tiling, tiles);
}

namespace {

// One method over the view's fragments: its pixels, its comparison with the truth (and, on
// meshes, the same fed the exact frame) and, when asked, its single-threaded cost on
// `timed` (a GLSL method is timed in the same call as its evaluation: one upload, every
// fragment, since a GL draw has a fixed cost). `timingMs` gets the time spent timing.
MethodFrame measureMethod(const Scene& scene, const ViewSpec& view, const MethodConfig& cfg,
                          const FragmentList& frags, const FragmentList& timed,
                          MethodTextureCache& textures, const TimingSpec& timing, RenderResult& r,
                          bool keepImages, double& timingMs) {
    const int W = r.camera.width(), H = r.camera.height();
    double s = std::isfinite(cfg.scale) ? cfg.scale : view.displacement.scale;
    double b = std::isfinite(cfg.bias) ? cfg.bias : view.displacement.bias;
    const MethodTextures& tex = textures.get(s, b, needsDerivedMaps(cfg));
    MethodFrame mf;
    mf.config = cfg;
    mf.timingBackend = timingBackend(cfg);
    auto te = Clock::now();
    const bool gl = cfg.kind == MethodKind::Glsl;
    mf.pixels = gl ? evaluateGlsl(cfg, frags, tex, W, H, false,
                                  timing.repeats > 0 ? &mf.nsPerPixel : nullptr, timing.repeats)
                   : evaluateMethod(cfg, frags, tex, W, H);
    r.timingsMs["methods_eval"] += msSince(te);
    const Texture& map = scene.height;
    mf.stats = compareWithTruth(r.truth, mf.pixels, map.width, map.height, map.address,
                                keepImages ? &mf.errTexels : nullptr);
    if (scene.isMesh) {
        auto exact = evaluateMethod(cfg, frags, tex, W, H, true);
        mf.statsExactFrame = compareWithTruth(r.truth, exact, map.width, map.height, map.address);
        mf.haveExactFrame = true;
    }
    if (timing.repeats > 0 && !gl) {
        auto tt = Clock::now();
        mf.nsPerPixel = timeMethodNsPerPixel(cfg, timed, tex, timing.repeats);
        timingMs += msSince(tt);
    }
    if (!keepImages) mf.pixels = {};
    return mf;
}

// Rasterisation, methods and comparison against given truth frames of `camera`, the camera
// of `view`.
RenderResult renderWithTruth(const Scene& scene, const ViewSpec& view, const Camera& camera,
                             TruthFrames&& truth, const std::vector<MethodConfig>& configs,
                             MethodTextureCache& textures, const TimingSpec& timing,
                             bool keepImages) {
    RenderResult r;
    r.view = view;
    r.camera = camera;
    r.truthBuild = truth.build;
    r.truthBlocks = truth.blocks;
    r.truth = std::move(truth.truth);
    r.timingsMs["trace"] = truth.traceMs;
    if (truth.haveFine) {
        r.truthBuildFine = truth.buildFine;
        r.uncertainty = compareTruthFrames(r.truth, truth.fine, scene.height, scene.height.address);
        r.uncertainty.rate = scene.truth.rate;
        r.uncertainty.rateFine = 2 * scene.truth.rate;
        r.haveUncertainty = true;
        r.timingsMs["trace_fine"] = truth.fineMs;
    }

    auto t2 = Clock::now();
    r.fragments = rasterize(sceneBaseMesh(scene, camera), camera, {scene.cullBackFaces}, &r.raster);
    FragmentList frags = compactFragments(r.fragments);
    FragmentList timed = sampleFragments(frags, timing.maxFragments, timing.seed);
    r.timingsMs["raster"] = msSince(t2);

    auto t3 = Clock::now();
    double timingMs = 0;
    for (const MethodConfig& cfg : configs)
        r.methods.push_back(measureMethod(scene, view, cfg, frags, timed, textures, timing, r,
                                          keepImages, timingMs));
    r.timingsMs["methods"] = msSince(t3) - timingMs;
    r.timingsMs["method_timing"] = timingMs;
    if (!keepImages) r.fragments = {};
    return r;
}

}  // namespace

RenderResult renderView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                        const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                        const TimingSpec& timing, bool keepImages) {
    const Camera camera = makeCamera(scene, view);
    return renderWithTruth(scene, view, camera, traceTruth(camera, truths), configs, textures,
                           timing, keepImages);
}

double estimateViewBytes(const Scene& scene, int width, int height, size_t methods,
                         bool writesImages, bool truthInBlocks) {
    const double pixels = double(width) * height;
    // Per pixel: truth at two rates, the raster's fragment and depth, the fragment list
    // (FragmentList: 68 bytes per covered pixel), per method its pixels, error and the
    // comparison's sorted copy, twice on meshes (the exact-frame pass).
    double perPixel = 2.0 * sizeof(TruthSample) + sizeof(Fragment) + sizeof(double) + 68;
    perPixel += double(methods) * (sizeof(MethodPixel) + sizeof(float) + sizeof(double)) *
                (scene.isMesh ? 2 : 1);
    // Outputs: the EXR planes (6 + 3 per method floats), their interleaved copy, the
    // encoded file (at most as large), and one error map's canvas.
    if (writesImages) perPixel += (6.0 + 3.0 * double(methods)) * sizeof(float) * 3 + 3;
    double truth = 0;
    if (!scene.isMesh) {
        TruthWindow whole;  // not limited: the whole base
        truth = truthVertices(scene, whole) * kTruthBytesPerGridVertex;
        if (truthInBlocks) truth = std::min(truth, double(scene.truth.memoryMb) * 1024 * 1024);
    }
    return pixels * perPixel + truth;
}

void checkViewMemory(const Scene& scene, int width, int height, size_t methods, bool writesImages,
                     bool truthInBlocks, const std::string& field) {
    checkMemory(estimateViewBytes(scene, width, height, methods, writesImages, truthInBlocks),
                scene.file, field, std::to_string(width) + "x" + std::to_string(height),
                "a " + std::to_string(width) + "x" + std::to_string(height) + " frame with " +
                    std::to_string(methods) + " method(s) and its truth");
}

RenderResult renderFrame(const Scene& scene, const RenderOptions& options) {
    const Camera camera = makeCamera(scene);
    MethodTextureCache textures(scene.height, scene.uvExtent);
    const TimingSpec timing{options.timingRepeats, 0, 1};
    auto t0 = Clock::now();
    const double budget = double(scene.truth.memoryMb) * 1024 * 1024 / kTruthBytesPerGridVertex;
    if (!scene.isMesh) {
        TruthWindow whole = viewWindow(scene.plane, scene.height, scene.displacement, camera);
        TruthFrames f;
        if (truthVertices(scene, whole) > budget && traceTruthInBlocks(scene, camera, budget, f)) {
            double truthMs = msSince(t0);
            RenderResult r = renderWithTruth(scene, scene.view(), camera, std::move(f),
                                             scene.methods, textures, timing, true);
            r.timingsMs["truth_total"] = truthMs;
            return r;
        }
    }
    TruthBuilder builder(scene);
    builder.limitToView(camera, scene.displacement);
    TruthPair truths = builder.build(scene.displacement, scene.truth.uncertainty);
    double buildMs = msSince(t0);
    RenderResult r = renderView(scene, scene.view(), truths, scene.methods, textures, timing);
    r.timingsMs["tessellate"] = r.truthBuild.tessellateMs;
    r.timingsMs["build"] = r.truthBuild.buildMs;
    r.timingsMs["truth_total"] = buildMs;
    return r;
}

}  // namespace pgt
