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
#include "methods/registry.h"

namespace pgt {

FragmentList compactFragments(const Image2D<Fragment>& frags) {
    FragmentList list;
    for (int y = 0; y < frags.height; ++y)
        for (int x = 0; x < frags.width; ++x) {
            const Fragment& f = frags.at(x, y);
            if (!f.covered) continue;
            list.pixel.push_back(y * frags.width + x);
            list.uv0.push_back(Vec2f(f.uv0));
            list.view.push_back(Vec3f(f.viewTangent));
            list.uv0d.push_back(f.uv0);
            list.viewd.push_back(f.viewTangent);
            list.viewExact.push_back(Vec3f(f.viewTangentExact));
            list.viewExactd.push_back(f.viewTangentExact);
        }
    return list;
}

FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed) {
    if (count <= 0 || size_t(count) >= all.size()) return all;
    std::vector<size_t> idx(all.size());
    for (size_t k = 0; k < idx.size(); ++k) idx[k] = k;
    std::mt19937 rng(seed);
    std::shuffle(idx.begin(), idx.end(), rng);
    idx.resize(size_t(count));
    std::sort(idx.begin(), idx.end());  // keep the scan order's memory locality
    FragmentList out;
    for (size_t k : idx) {
        out.pixel.push_back(all.pixel[k]);
        out.uv0.push_back(all.uv0[k]);
        out.view.push_back(all.view[k]);
        out.uv0d.push_back(all.uv0d[k]);
        out.viewd.push_back(all.viewd[k]);
        out.viewExact.push_back(all.viewExact[k]);
        out.viewExactd.push_back(all.viewExactd[k]);
    }
    return out;
}

MethodTextures makeMethodTextures(const Texture& height, double scale, double bias,
                                  const UvExtent& uvExtent, bool needDerived) {
    MethodTextures t;
    t.height = &height;
    t.scale = scale;
    t.bias = bias;
    t.uvExtent = uvExtent;
    if (needDerived)
        t.derived = std::make_unique<DerivedMaps>(makeDerivedMaps(height, scale, bias));
    return t;
}

const MethodTextures& MethodTextureCache::get(double scale, double bias, bool needDerived) {
    auto key = std::make_pair(scale, bias);
    auto it = cache_.find(key);
    if (it != cache_.end() && (!needDerived || it->second.derived)) return it->second;
    cache_[key] = makeMethodTextures(height_, scale, bias, uvExtent_, needDerived);
    return cache_[key];
}

std::shared_ptr<const BaseTessellation> TruthBuilder::tessellate(int r) const {
    if (scene_.isMesh && scene_.mesh.truthSurface == "limit")
        return tessellateLimitSurface(scene_.height, *scene_.mesh.cage, scene_.mesh.scheme,
                                      scene_.worldPerUv(), r);
    if (scene_.isMesh)
        return tessellateDrawnMesh(scene_.height, scene_.mesh.drawn->mesh, scene_.worldPerUv(), r);
    return tessellatePlane(scene_.height, scene_.plane, r, window_);
}

void TruthBuilder::limitToView(const Camera& camera, const Displacement& disp, PixelRect block) {
    PGT_CHECK(!base_ && !fine_);
    if (scene_.isMesh) return;
    window_ = viewWindow(scene_.plane, scene_.height, disp, camera, block);
    // A whole view's window is only worth it when it is clearly smaller than the tile.
    const double T = scene_.plane.tiling;
    const Vec2d extent = window_.uvMax - window_.uvMin;
    if (window_.empty || (block.empty() && window_.limited && extent.x * extent.y >= 0.5 * T * T))
        window_ = {};
}

TruthPair TruthBuilder::build(const Displacement& disp, bool withUncertainty) {
    const int rate = scene_.truth.rate;
    // A mesh's truth is an explicit triangle list; grids are for planes.
    TruthGeometry geometry = scene_.isMesh ? TruthGeometry::Triangles : scene_.truth.geometry;
    // A window of an infinite plane is traced as it is: it covers every hit of the view.
    bool periodic = !scene_.isMesh && scene_.plane.infinite && !window_.limited;
    if (!base_) base_ = tessellate(rate);
    TruthPair p;
    p.truth = std::make_unique<TruthSurface>(base_, disp, geometry, periodic);
    if (withUncertainty) {
        if (!fine_) fine_ = tessellate(2 * rate);
        p.fine = std::make_unique<TruthSurface>(fine_, disp, geometry, periodic);
    }
    return p;
}

const TruthPair& TruthBuilder::update(const Displacement& disp, bool withUncertainty) {
    if (!current_.truth || (withUncertainty && !current_.fine)) {
        current_ = build(disp, withUncertainty);
        return current_;
    }
    current_.truth->setDisplacement(disp);
    if (withUncertainty)
        current_.fine->setDisplacement(disp);
    else
        current_.fine.reset();
    return current_;
}

BaseMesh sceneBaseMesh(const Scene& scene, const Camera& camera) {
    if (scene.isMesh) return scene.mesh.drawn->mesh;
    int tiles =
        scene.plane.infinite ? tilesToCover(camera, scene.plane.center, scene.plane.size) : 0;
    return makePlaneMesh(scene.plane.center, scene.plane.size, scene.plane.tiling, tiles);
}

namespace {

template <class Real>
MethodContext<Real> makeContext(const MethodTextures& tex) {
    MethodContext<Real> c;
    c.height = tex.height;
    if (tex.derived) {
        c.normal = &tex.derived->normal;
        c.parallax = &tex.derived->parallax;
    }
    // s and b are rounded to the method's precision once, as a shader uniform would be.
    c.scale = Real(tex.scale);
    c.bias = Real(tex.bias);
    return c;
}

template <class Real>
MethodPixel runOne(const MethodConfig& cfg, const MethodTextures& tex, Vec2<Real> uv0,
                   Vec3<Real> v) {
    MethodContext<Real> c = makeContext<Real>(tex);
    Vec2<Real> uv = runMethod<Real>(cfg, c, uv0, v);
    MethodPixel p;
    p.covered = true;
    p.uv = Vec2d(uv);
    p.fetches = uint32_t(c.fetches);
    p.flags = c.flags;
    // LearnOpenGL's discard: x > 1 || y > 1 || x < 0 || y < 0 (NaN is not discarded).
    if (cfg.discardOutside && !tex.uvExtent.contains(double(uv.x), double(uv.y))) p.covered = false;
    return p;
}

}  // namespace

std::string timingBackend(const MethodConfig& cfg) {
    if (cfg.kind != MethodKind::Glsl) return "cpu";
    const GlInfo& gl = glContext();
    return gl.software ? "gl wall clock: " + gl.renderer + " (software renderer, not a GPU time)"
                       : "gl timer query: " + gl.renderer;
}

namespace {

// A GLSL method's frame: its shader in OpenGL over the same float inputs.
// The GL's time per pixel: timer queries on a GPU; on a software GL the wall clock around
// the draw, because llvmpipe's GL_TIME_ELAPSED does not cover its deferred rasterisation
// (measured: 0.2-16 ns/px against 12-80 ns/px between two glFinish).
double glNsPerPixel(const GlslRun& run) {
    return glContext().software ? run.wallNsPerPixel : run.gpuNsPerPixel;
}

// A GLSL method over fragment inputs, with the maps and (s, b) of `tex`.
GlslRun runGlslWith(const MethodConfig& cfg, const MethodTextures& tex,
                    const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view, int repeats) {
    return runGlsl(*cfg.glsl, *tex.height, tex.derived ? &tex.derived->normal : nullptr,
                   tex.derived ? &tex.derived->parallax : nullptr, tex.scale, tex.bias, uv0, view,
                   repeats);
}

// `nsPerPixel` (optional): also time the draw, median of `repeats`.
Image2D<MethodPixel> evaluateGlsl(const MethodConfig& cfg, const FragmentList& frags,
                                  const MethodTextures& tex, int width, int height, bool exactFrame,
                                  double* nsPerPixel = nullptr, int repeats = 0) {
    Image2D<MethodPixel> out(width, height);
    GlslRun run = runGlslWith(cfg, tex, frags.uv0, exactFrame ? frags.viewExact : frags.view,
                              nsPerPixel ? repeats : 0);
    if (nsPerPixel) *nsPerPixel = glNsPerPixel(run);
    for (size_t k = 0; k < frags.pixel.size(); ++k) {
        MethodPixel& p = out.data[size_t(frags.pixel[k])];
        p.covered = true;
        p.uv = Vec2d(run.uv[k]);
        p.fetches = run.fetches[k];
        const Vec2f uv = run.uv[k];
        if (cfg.discardOutside && !tex.uvExtent.contains(double(uv.x), double(uv.y)))
            p.covered = false;
    }
    return out;
}

}  // namespace

Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height,
                                    bool exactFrame) {
    if (cfg.kind == MethodKind::Glsl)
        return evaluateGlsl(cfg, frags, tex, width, height, exactFrame);
    Image2D<MethodPixel> out(width, height);
    const size_t n = frags.pixel.size();
    const auto& view = exactFrame ? frags.viewExact : frags.view;
    const auto& viewd = exactFrame ? frags.viewExactd : frags.viewd;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            out.data[size_t(frags.pixel[k])] =
                cfg.doublePrecision ? runOne<double>(cfg, tex, frags.uv0d[k], viewd[k])
                                    : runOne<float>(cfg, tex, frags.uv0[k], view[k]);
        }
    });
    return out;
}

double timeMethodNsPerPixel(const MethodConfig& cfg, const FragmentList& frags,
                            const MethodTextures& tex, int repeats) {
    const size_t n = frags.pixel.size();
    if (n == 0 || repeats < 1) return 0.0;
    // A GLSL method: the GL time of its draw (glNsPerPixel), median of the repeats.
    if (cfg.kind == MethodKind::Glsl)
        return glNsPerPixel(runGlslWith(cfg, tex, frags.uv0, frags.view, repeats));
    std::vector<double> samples;
    volatile double sink = 0;  // keeps the results alive so the loop is not optimised away
    for (int r = 0; r < repeats; ++r) {
        double acc = 0;
        auto t0 = Clock::now();
        if (cfg.doublePrecision) {
            for (size_t k = 0; k < n; ++k) {
                MethodContext<double> c = makeContext<double>(tex);
                Vec2d uv = runMethod<double>(cfg, c, frags.uv0d[k], frags.viewd[k]);
                acc += uv.x + uv.y;
            }
        } else {
            for (size_t k = 0; k < n; ++k) {
                MethodContext<float> c = makeContext<float>(tex);
                Vec2f uv = runMethod<float>(cfg, c, frags.uv0[k], frags.view[k]);
                acc += double(uv.x + uv.y);
            }
        }
        samples.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
                          double(n));
        sink = sink + acc;
    }
    std::sort(samples.begin(), samples.end());
    return samples[samples.size() / 2];
}

TruthFrames traceTruth(const Camera& camera, const TruthPair& truths) {
    TruthFrames f;
    f.build = truths.truth->stats();
    auto t0 = Clock::now();
    truths.truth->traceFrame(camera, f.truth);
    f.traceMs = msSince(t0);
    if (truths.fine) {
        auto t1 = Clock::now();
        f.buildFine = truths.fine->stats();
        truths.fine->traceFrame(camera, f.fine);
        f.haveFine = true;
        f.fineMs = msSince(t1);
    }
    return f;
}

RenderResult renderView(const Scene& scene, const Camera& camera, const TruthPair& truths,
                        const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                        const TimingSpec& timing, bool keepImages) {
    return renderWithTruth(scene, camera, traceTruth(camera, truths), configs, textures, timing,
                           keepImages);
}

RenderResult renderWithTruth(const Scene& scene, const Camera& camera, TruthFrames&& truth,
                             const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                             const TimingSpec& timing, bool keepImages) {
    RenderResult r;
    r.camera = camera;
    const int W = camera.width(), H = camera.height();
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
    for (const MethodConfig& cfg : configs) {
        double s = std::isfinite(cfg.scale) ? cfg.scale : scene.displacement.scale;
        double b = std::isfinite(cfg.bias) ? cfg.bias : scene.displacement.bias;
        const MethodTextures& tex = textures.get(s, b, needsDerivedMaps(cfg));
        MethodFrame mf;
        mf.config = cfg;
        mf.timingBackend = timingBackend(cfg);
        auto te = Clock::now();
        // A GLSL method is timed in the same call (one upload; every fragment, since a GL
        // draw has a fixed cost); C++ methods below, on the timed subset.
        const bool gl = cfg.kind == MethodKind::Glsl;
        mf.pixels = gl ? evaluateGlsl(cfg, frags, tex, W, H, false,
                                      timing.repeats > 0 ? &mf.nsPerPixel : nullptr, timing.repeats)
                       : evaluateMethod(cfg, frags, tex, W, H);
        r.timingsMs["methods_eval"] += msSince(te);
        mf.stats = compareWithTruth(r.truth, mf.pixels, scene.height.width, scene.height.height,
                                    scene.height.address, keepImages ? &mf.errTexels : nullptr);
        if (scene.isMesh) {
            auto exact = evaluateMethod(cfg, frags, tex, W, H, true);
            mf.statsExactFrame = compareWithTruth(r.truth, exact, scene.height.width,
                                                  scene.height.height, scene.height.address);
            mf.haveExactFrame = true;
        }
        if (timing.repeats > 0 && !gl) {
            auto tt = Clock::now();
            mf.nsPerPixel = timeMethodNsPerPixel(cfg, timed, tex, timing.repeats);
            timingMs += msSince(tt);
        }
        if (!keepImages) mf.pixels = {};
        r.methods.push_back(std::move(mf));
    }
    r.timingsMs["methods"] = msSince(t3) - timingMs;
    r.timingsMs["method_timing"] = timingMs;
    if (!keepImages) r.fragments = {};
    return r;
}

namespace {

// Plane vertices of a truth (and its 2x-rate twin) over the whole tile or a window.
double truthVertices(const Scene& scene, const TruthWindow& w) {
    double sum = 0;
    for (int r : {scene.truth.rate, scene.truth.uncertainty ? 2 * scene.truth.rate : 0}) {
        if (r == 0) continue;
        double u =
            r * scene.height.width * (w.limited ? w.uvMax.x - w.uvMin.x : scene.plane.tiling);
        double v =
            r * scene.height.height * (w.limited ? w.uvMax.y - w.uvMin.y : scene.plane.tiling);
        sum += (u + 2) * (v + 2);
    }
    return sum;
}

// The view's truth traced in n x n pixel blocks, each over a tessellation of only what the
// block sees, so peak memory is one block's (large maps in a whole-map view).
// Returns false (frames untouched) when no n <= 16 brings every block under the budget.
bool traceTruthInBlocks(const Scene& scene, const Camera& camera, double budgetVertices,
                        TruthFrames& f) {
    const int W = camera.width(), H = camera.height();
    for (int n = 2; n <= 16; ++n) {
        std::vector<PixelRect> blocks;
        bool fits = true;
        for (int by = 0; by < n && fits; ++by)
            for (int bx = 0; bx < n && fits; ++bx) {
                PixelRect b{W * bx / n, H * by / n, W * (bx + 1) / n, H * (by + 1) / n};
                TruthWindow w =
                    viewWindow(scene.plane, scene.height, scene.displacement, camera, b);
                fits = w.limited && (w.empty || truthVertices(scene, w) <= budgetVertices);
                if (w.empty) continue;  // sees no part of the plane: every pixel misses
                blocks.push_back(b);
            }
        if (!fits) continue;
        f.truth = Image2D<TruthSample>(W, H);
        if (scene.truth.uncertainty) f.fine = Image2D<TruthSample>(W, H), f.haveFine = true;
        for (const PixelRect& b : blocks) {
            TruthBuilder builder(scene);
            builder.limitToView(camera, scene.displacement, b);
            TruthPair pair = builder.build(scene.displacement, scene.truth.uncertainty);
            auto t0 = Clock::now();
            pair.truth->traceBlock(camera, f.truth, b);
            f.traceMs += msSince(t0);
            if (pair.truth->stats().vertices > f.build.vertices) f.build = pair.truth->stats();
            if (pair.fine) {
                auto t1 = Clock::now();
                pair.fine->traceBlock(camera, f.fine, b);
                f.fineMs += msSince(t1);
                if (pair.fine->stats().vertices > f.buildFine.vertices)
                    f.buildFine = pair.fine->stats();
            }
        }
        f.blocks = n * n;
        return true;
    }
    return false;
}

}  // namespace

double estimateViewBytes(const Scene& scene, int width, int height, size_t methods,
                         bool writesImages, bool truthInBlocks) {
    const double pixels = double(width) * height;
    // Per pixel: truth at two rates, the raster's fragment and depth, the fragment list
    // (FragmentList: 100 bytes per covered pixel), per method its pixels, error and the
    // comparison's sorted copy, twice on meshes (the exact-frame pass).
    double perPixel = 2.0 * sizeof(TruthSample) + sizeof(Fragment) + sizeof(double) + 100;
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
            RenderResult r =
                renderWithTruth(scene, camera, std::move(f), scene.methods, textures, timing);
            r.timingsMs["truth_total"] = truthMs;
            return r;
        }
    }
    TruthBuilder builder(scene);
    builder.limitToView(camera, scene.displacement);
    TruthPair truths = builder.build(scene.displacement, scene.truth.uncertainty);
    double buildMs = msSince(t0);
    RenderResult r = renderView(scene, camera, truths, scene.methods, textures, timing);
    r.timingsMs["tessellate"] = r.truthBuild.tessellateMs;
    r.timingsMs["build"] = r.truthBuild.buildMs;
    r.timingsMs["truth_total"] = buildMs;
    return r;
}

}  // namespace pgt
