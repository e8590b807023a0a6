// Method evaluation over fragment lists, C++ and GLSL, and method timing (study/evaluate.h).
#include "study/evaluate.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "core/clock.h"
#include "core/error.h"
#include "gl/glsl_method.h"
#include "methods/registry.h"

namespace pgt {

MethodTextures makeMethodTextures(const Texture& height, double scale, double bias,
                                  const UvExtent& uvExtent, bool needDerived) {
    MethodTextures t;
    t.height = &height;
    t.scale = scale;
    t.bias = bias;
    t.uvExtent = uvExtent;
    t.glMaps = std::make_shared<GlMapUploads>();  // empty until a GLSL method reads the maps
    if (needDerived)
        t.derived = std::make_unique<DerivedMaps>(makeDerivedMaps(height, scale, bias));
    return t;
}

namespace {
// The (s, b) a method runs with in a view: its own where it has one (MODEL.md §3, UV units).
std::pair<double, double> methodScaleBias(const MethodConfig& cfg, const Displacement& view) {
    return {std::isfinite(cfg.scale) ? cfg.scale : view.scale,
            std::isfinite(cfg.bias) ? cfg.bias : view.bias};
}
}  // namespace

namespace {
// A per-map precomputation, built (and its time kept) on first use.
template <class T, class Build>
void buildOnce(std::shared_ptr<const T>& map, double& ms, Build build) {
    if (map) return;
    auto t0 = Clock::now();
    map = std::make_shared<const T>(build());
    ms = msSince(t0);
}
}  // namespace

const MethodTextures& MethodTextureCache::get(const MethodConfig& cfg, const Displacement& view) {
    const auto key = methodScaleBias(cfg, view);
    const bool needDerived = needsDerivedMaps(cfg), needPyramid = needsMinMaxPyramid(cfg);
    if (needPyramid) buildOnce(pyramid_, pyramidMs_, [&] { return buildMinMaxPyramid(height_); });
    auto it = cache_.find(key);
    if (it == cache_.end())
        it = cache_
                 .emplace(key, makeMethodTextures(height_, key.first, key.second, uvExtent_,
                                                  needDerived))
                 .first;
    // An entry made for other methods gains what this one needs; it is never replaced, since
    // methods set up before hold it.
    if (needDerived && !it->second.derived)
        it->second.derived =
            std::make_unique<DerivedMaps>(makeDerivedMaps(height_, key.first, key.second));
    if (needPyramid && !it->second.pyramid) it->second.pyramid = pyramid_;  // a hit only reads
    const int sign = key.first < 0 ? 1 : 0;  // cone maps: one per sign of s
    if (needsConeMap(cfg) && !it->second.cone) {
        buildOnce(cone_[sign], coneMs_[sign], [&] { return buildConeMap(height_, sign); });
        it->second.cone = cone_[sign];
    }
    if (needsRelaxedConeMap(cfg) && !it->second.relaxedCone) {
        buildOnce(relaxed_[sign], relaxedMs_[sign],
                  [&] { return buildRelaxedConeMap(height_, *cone_[sign]); });
        it->second.relaxedCone = relaxed_[sign];
    }
    return it->second;
}

double MethodTextureCache::precomputeMs(const MethodConfig& cfg, const Displacement& view) const {
    double ms = needsMinMaxPyramid(cfg) ? pyramidMs_ : 0.0;
    const int sign = methodScaleBias(cfg, view).first < 0 ? 1 : 0;
    if (needsConeMap(cfg)) ms += coneMs_[sign];
    if (needsRelaxedConeMap(cfg)) ms += relaxedMs_[sign];
    return ms;
}

const MethodTextures& MethodTextureCache::at(const MethodConfig& cfg,
                                             const Displacement& view) const {
    auto it = cache_.find(methodScaleBias(cfg, view));
    PGT_CHECK(it != cache_.end());
    return it->second;
}

namespace {

template <class Real>
MethodPixel runOne(const MethodConfig& cfg, const MethodTextures& tex, Vec2<Real> uv0,
                   Vec3<Real> v) {
    MethodContext<Real> c = makeMethodContext<Real>(tex);
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

// A list rounded to float, as a GPU's varyings are.
template <class To, class From>
std::vector<To> toFloat(const std::vector<From>& values) {
    return std::vector<To>(values.begin(), values.end());
}

// A GLSL method over the fragments (V in the exact frame or not), with the maps and (s, b)
// of `tex`.
GlslRun runGlslWith(const MethodConfig& cfg, const MethodTextures& tex, const FragmentList& frags,
                    bool exactFrame, int repeats) {
    return runGlsl(*cfg.glsl, *tex.height, tex.derived ? &tex.derived->normal : nullptr,
                   tex.derived ? &tex.derived->parallax : nullptr, tex.scale, tex.bias,
                   toFloat<Vec2f>(frags.uv0),
                   toFloat<Vec3f>(exactFrame ? frags.viewExact : frags.view), repeats,
                   tex.glMaps.get(), tex.pyramid.get(), tex.cone.get(), tex.relaxedCone.get());
}

}  // namespace

// `nsPerPixel` (optional): also time the draw, median of `repeats`.
Image2D<MethodPixel> evaluateGlsl(const MethodConfig& cfg, const FragmentList& frags,
                                  const MethodTextures& tex, int width, int height, bool exactFrame,
                                  double* nsPerPixel, int repeats) {
    Image2D<MethodPixel> out(width, height);
    GlslRun run = runGlslWith(cfg, tex, frags, exactFrame, nsPerPixel ? repeats : 0);
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

Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height,
                                    bool exactFrame) {
    if (cfg.kind == MethodKind::Glsl)
        return evaluateGlsl(cfg, frags, tex, width, height, exactFrame);
    Image2D<MethodPixel> out(width, height);
    const size_t n = frags.pixel.size();
    const auto& view = exactFrame ? frags.viewExact : frags.view;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            out.data[size_t(frags.pixel[k])] =
                cfg.doublePrecision ? runOne<double>(cfg, tex, frags.uv0[k], view[k])
                                    : runOne<float>(cfg, tex, Vec2f(frags.uv0[k]), Vec3f(view[k]));
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
        return glNsPerPixel(runGlslWith(cfg, tex, frags, false, repeats));
    // The float inputs rounded before the clock starts: the time is the method's alone.
    const std::vector<Vec2f> uv0 = toFloat<Vec2f>(frags.uv0);
    const std::vector<Vec3f> view = toFloat<Vec3f>(frags.view);
    std::vector<double> samples;
    volatile double sink = 0;  // keeps the results alive so the loop is not optimised away
    for (int r = 0; r < repeats; ++r) {
        double acc = 0;
        auto t0 = Clock::now();
        if (cfg.doublePrecision) {
            for (size_t k = 0; k < n; ++k) {
                MethodContext<double> c = makeMethodContext<double>(tex);
                Vec2d uv = runMethod<double>(cfg, c, frags.uv0[k], frags.view[k]);
                acc += uv.x + uv.y;
            }
        } else {
            for (size_t k = 0; k < n; ++k) {
                MethodContext<float> c = makeMethodContext<float>(tex);
                Vec2f uv = runMethod<float>(cfg, c, uv0[k], view[k]);
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

}  // namespace pgt
