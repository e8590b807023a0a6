// Method evaluation over fragment lists, C++ and GLSL, and method timing
// (evaluate/evaluate.h).
#include "evaluate/evaluate.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <set>

#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/overloaded.h"
#include "core/percentile.h"
#include "heightfield/mipmaps.h"
#include "methods/builtin/shadow.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "methods/shader/glsl_method.h"
#include "methods/shader/glsl_spec.h"
#include "methods/shader/vertex_stage.h"

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
// The (s, b) a method runs with in a view: its own where it has one (docs/model.md §3, UV units).
std::pair<double, double> methodScaleBias(const MethodConfig& cfg, const Displacement& view) {
    return cfg.scaleBias(view.scale, view.bias);
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

MethodTextureCache& MethodTextureCache::stored(StorageFormat format) {
    std::unique_ptr<Stored>& s = stored_[format];
    if (!s) {
        s = std::make_unique<Stored>();
        s->map = storedMap(height_, format == StorageFormat::Unorm8 ? 8 : 16);
        s->cache = std::make_unique<MethodTextureCache>(s->map, uvExtent_, format);
    }
    return *s->cache;
}

const MethodTextureCache& MethodTextureCache::storedAt(StorageFormat format) const {
    auto it = stored_.find(format);
    PGT_CHECK(it != stored_.end());
    return *it->second->cache;
}

void MethodTextureCache::clear() {
    cache_.clear();
    for (auto& [format, s] : stored_) s->cache->clear();
}

const MethodTextures& MethodTextureCache::get(const MethodConfig& cfg, const Displacement& view) {
    if (cfg.format != own_) return stored(cfg.format).get(cfg, view);
    const auto key = methodScaleBias(cfg, view);
    auto it = cache_.find(key);
    if (it == cache_.end())
        it = cache_
                 .emplace(key, makeMethodTextures(height_, key.first, key.second, uvExtent_, false))
                 .first;
    // An entry made for other methods gains what this one needs; what it holds is never
    // replaced, since methods set up before read it (a hit only reads).
    MethodTextures& e = it->second;
    const int sign = key.first < 0 ? 1 : 0;  // cone maps: one per sign of s
    const MapSet want = needs(cfg);
    for (const MapKindInfo& m : kMapKindTable) {
        if (!want.has(m.kind)) continue;
        switch (m.kind) {
            case MapKind::Height:
                break;  // every entry has it
            case MapKind::Normal:
            case MapKind::Parallax:  // Lengyel FGED 2's pair, made together
                if (!e.derived)
                    e.derived = std::make_unique<DerivedMaps>(
                        makeDerivedMaps(height_, key.first, key.second));
                break;
            case MapKind::Pyramid:
                buildOnce(pyramid_, pyramidMs_, [&] { return buildMinMaxPyramid(height_); });
                e.pyramid = pyramid_;
                break;
            case MapKind::RelaxedCone:  // made from the cone map
            case MapKind::Cone:
                buildOnce(cone_[sign], coneMs_[sign], [&] { return buildConeMap(height_, sign); });
                if (m.kind == MapKind::Cone) {
                    e.cone = cone_[sign];
                    break;
                }
                buildOnce(relaxed_[sign], relaxedMs_[sign],
                          [&] { return buildRelaxedConeMap(height_, *cone_[sign]); });
                e.relaxedCone = relaxed_[sign];
                break;
        }
    }
    return e;
}

double estimateMapBytes(const Texture& height, const std::vector<MethodConfig>& configs) {
    // Each stored format its own maps, and a rounded copy of the height map (with its chain).
    std::map<StorageFormat, std::vector<MethodConfig>> byFormat;
    for (const MethodConfig& cfg : configs) byFormat[cfg.format].push_back(cfg);
    if (byFormat.size() > 1 ||
        (!byFormat.empty() && byFormat.begin()->first != StorageFormat::Float)) {
        double bytes = 0;
        for (auto& [format, group] : byFormat) {
            for (MethodConfig& c : group) c.format = StorageFormat::Float;
            bytes += estimateMapBytes(height, group);
            if (format != StorageFormat::Float)
                bytes += 4.0 * double(height.width) * double(height.height) *
                         (height.mips ? 4.0 / 3.0 : 1.0);
        }
        return bytes;
    }
    const double texels = double(height.width) * double(height.height);
    const double chain = height.mips ? 4.0 / 3.0 : 1.0;
    // Per kind: whether any configuration reads it, and the (s, b) a per-(s, b) one is made
    // for (1e300: the view's).
    MapSet read, inGl;
    std::set<std::pair<double, double>> displacements;
    for (const MethodConfig& cfg : configs) {
        const MapSet want = needs(cfg);
        read |= want;
        if (runsInGl(cfg)) inGl |= want, inGl.add(MapKind::Height);
        if (want.has(MapKind::Normal) || want.has(MapKind::Parallax))
            displacements.insert(cfg.scaleBias(1e300, 1e300));
    }
    if (read.has(MapKind::RelaxedCone)) read.add(MapKind::Cone);
    double perTexel = 0;
    for (const MapKindInfo& m : kMapKindTable) {
        const double copies = m.perDisplacement ? chain * double(displacements.size()) : 1.0;
        if (read.has(m.kind)) perTexel += m.bytesPerTexel * copies;
        const double glChain = m.kind == MapKind::Height ? chain : copies;
        if (inGl.has(m.kind)) perTexel += 4.0 * m.glChannels * glChain;
    }
    return perTexel * texels;
}

double MethodTextureCache::precomputeMs(const MethodConfig& cfg, const Displacement& view) const {
    if (cfg.format != own_) return storedAt(cfg.format).precomputeMs(cfg, view);
    const int sign = methodScaleBias(cfg, view).first < 0 ? 1 : 0;
    const MapSet want = needs(cfg);
    double ms = want.has(MapKind::Pyramid) ? pyramidMs_ : 0.0;
    if (want.has(MapKind::Cone) || want.has(MapKind::RelaxedCone)) ms += coneMs_[sign];
    if (want.has(MapKind::RelaxedCone)) ms += relaxedMs_[sign];
    return ms;
}

const MethodTextures& MethodTextureCache::at(const MethodConfig& cfg,
                                             const Displacement& view) const {
    if (cfg.format != own_) return storedAt(cfg.format).at(cfg, view);
    auto it = cache_.find(methodScaleBias(cfg, view));
    PGT_CHECK(it != cache_.end());
    return it->second;
}

namespace {

// Whether `cfg` reads uv0's derivatives ("lod": "grad" over mipmapped maps), checked once a
// list: the raster makes them for every frame with such a method (rasterOptions).
bool readsDerivatives(const MethodConfig& cfg, const MethodTextures& tex,
                      const FragmentList& frags) {
    const bool reads = cfg.lodGrad && tex.height->mips;
    PGT_CHECK(!reads || frags.hasDerivatives());
    return reads;
}

// The level of detail of a fragment for a method that reads the derivatives, 0 otherwise.
template <class Real>
Real fragmentLod(bool reads, const MethodTextures& tex, const FragmentList& frags, size_t k) {
    if (!reads) return Real(0);
    return lodFromGradients(Vec2<Real>(frags.uvDx[k]), Vec2<Real>(frags.uvDy[k]), tex.height->width,
                            tex.height->height);
}

// One method on one fragment, then its shadow march toward `light` (tangent space; zero:
// the view has no light). The depth offset is -height / V.z (docs/model.md §6c). The cost
// (fetches here, time in cppPass) is the method's alone, comparable with GLSL methods, which
// run no march.
template <class Real>
MethodPixel runOne(const MethodConfig& cfg, const BuiltinMethod& b, const MethodTextures& tex,
                   Vec2<Real> uv0, Vec3<Real> v, Real lod, Vec3<Real> light) {
    MethodContext<Real> c = makeMethodContext<Real>(tex);
    c.lod = lod;
    Vec2<Real> uv = runMethod<Real>(b, c, uv0, v);
    MethodPixel p;
    p.covered = true;
    p.uv = Vec2d(uv);
    p.depth = float(-c.foundHeight / v.z);
    p.fetches = uint32_t(c.fetches);  // the method's own: the shadow march's are not counted
    if (light != Vec3<Real>(0)) p.shadow = runShadow(b, c, uv, light);
    p.flags = c.flags;
    // LearnOpenGL's discard: x > 1 || y > 1 || x < 0 || y < 0 (NaN is not discarded).
    if (cfg.discardOutside && !tex.uvExtent.contains(double(uv.x), double(uv.y))) p.covered = false;
    return p;
}

}  // namespace

void compileMethod(const MethodConfig& cfg) {
    if (const GlslSpec* g = cfg.shader()) compileGlsl(*g);
}

std::optional<GlUsed> glUsed() {
    const auto gl = glContextIfMade();
    if (!gl) return std::nullopt;
    return GlUsed{gl->vendor, gl->renderer, gl->version};
}

void selectGlDevice(const std::string& device) { setGlDevice(device); }

std::string timingBackend(const MethodConfig& cfg) {
    if (!runsInGl(cfg)) return "cpu";
    const GlInfo& gl = glContext();
    return gl.software ? "gl wall clock: " + gl.renderer + " (software renderer, not a GPU time)"
                       : "gl timer query: " + gl.renderer;
}

namespace {

// A list rounded to float, as a GPU's varyings are.
template <class To, class From>
std::vector<To> toFloat(const std::vector<From>& values) {
    return std::vector<To>(values.begin(), values.end());
}

// The V a configuration is handed: the exact frame's (the diagnostic pass), V per vertex
// ("V": "per_vertex", where the list has it) or per pixel.
const std::vector<Vec3d>& methodViews(const MethodConfig& cfg, const FragmentList& frags,
                                      bool exactFrame) {
    if (exactFrame) return frags.viewExact.size() == frags.size() ? frags.viewExact : frags.view;
    if (cfg.viewPerVertex && frags.viewVertex.size() == frags.size()) return frags.viewVertex;
    return frags.view;
}

GlslMaps glslMaps(const MethodConfig& cfg, const MethodTextures& tex) {
    return {tex.refs(), tex.scale, tex.bias, tex.glMaps.get(), cfg.lodGrad};
}

// The fragments as a GL draw of `cfg` takes them (V in the exact frame or not, and an
// engine's inputs where its shader reads them); in screen layout when `width` > 0.
GlslInputs glslInputs(const MethodConfig& cfg, const FragmentList& frags, bool exactFrame,
                      int width = 0, int height = 0, const VertexOutputs* vertex = nullptr) {
    GlslInputs in;
    in.uv0 = toFloat<Vec2f>(frags.uv0);
    in.view = toFloat<Vec3f>(methodViews(cfg, frags, exactFrame));
    if (readsEngineInputs(cfg)) {
        in.engine.resize(frags.size());
        for (size_t k = 0; k < frags.size(); ++k) in.engine[k] = frags.engineAt(k);
    }
    in.uvDx = toFloat<Vec2f>(frags.uvDx);
    in.uvDy = toFloat<Vec2f>(frags.uvDy);
    if (width > 0) {
        in.pixel = frags.pixel;
        in.frameWidth = width;
        in.frameHeight = height;
        in.triangle = frags.triangle;
        in.helpers.reserve(frags.helpers.size());
        for (const HelperLane& h : frags.helpers) {
            const Fragment& f = h.fragment;
            const Vec3d view = exactFrame ? f.viewTangentExact
                               : frags.viewVertex.empty() || !cfg.viewPerVertex
                                   ? f.viewTangent
                                   : h.inputs.viewVertex;
            in.helpers.push_back({h.at, f.triangle, Vec2f(f.uv0), Vec2f(f.uvDx), Vec2f(f.uvDy),
                                  Vec3f(view), h.inputs.engine});
        }
    }
    if (vertex) {  // the vertex stage's outputs at each fragment's and helper's barycentrics
        PGT_CHECK(frags.triangle.size() == frags.size() && frags.bary.size() == frags.size());
        in.links = int(vertex->offset.size());
        for (size_t k = 0; k < frags.size(); ++k)
            for (size_t l = 0; l < vertex->offset.size(); ++l)
                in.varyings.push_back(vertex->at(frags.triangle[k], frags.bary[k], l));
        for (size_t j = 0; j < in.helpers.size(); ++j)  // screen layout only
            for (size_t l = 0; l < vertex->offset.size(); ++l)
                in.helperVaryings.push_back(vertex->at(frags.helpers[j].fragment.triangle,
                                                       frags.helpers[j].inputs.bary, l));
    }
    return in;
}

}  // namespace

namespace {

Image2D<MethodPixel> evaluateShader(const MethodConfig& cfg, const GlslSpec& spec,
                                    const FragmentList& frags, const MethodTextures& tex, int width,
                                    int height, bool exactFrame, const VertexOutputs* vertex) {
    Image2D<MethodPixel> out(width, height);
    GlslRun run = runGlsl(spec, glslMaps(cfg, tex),
                          glslInputs(cfg, frags, exactFrame, width, height, vertex));
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

void evaluateBuiltin(const MethodConfig& cfg, const BuiltinMethod& b, const FragmentList& frags,
                     const MethodTextures& tex, int width, int height, bool exactFrame,
                     Image2D<MethodPixel>& out) {
    resetImage(out, width, height);
    const size_t n = frags.pixel.size();
    const auto& view = methodViews(cfg, frags, exactFrame);
    const bool reads = readsDerivatives(cfg, tex, frags);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            out.data[size_t(frags.pixel[k])] =
                b.doublePrecision ? runOne<double>(cfg, b, tex, frags.uv0[k], view[k],
                                                   fragmentLod<double>(reads, tex, frags, k),
                                                   frags.lightAt(k, exactFrame))
                                  : runOne<float>(cfg, b, tex, Vec2f(frags.uv0[k]), Vec3f(view[k]),
                                                  fragmentLod<float>(reads, tex, frags, k),
                                                  Vec3f(frags.lightAt(k, exactFrame)));
        }
    });
}

}  // namespace

void evaluateMethod(const MethodConfig& cfg, const FragmentList& frags, const MethodTextures& tex,
                    int width, int height, bool exactFrame, Image2D<MethodPixel>& out,
                    const VertexOutputs* vertex) {
    std::visit(Overloaded{[&](const BuiltinMethod& b) {
                              evaluateBuiltin(cfg, b, frags, tex, width, height, exactFrame, out);
                          },
                          [&](const ShaderMethod& m) {
                              out = evaluateShader(cfg, *m.spec, frags, tex, width, height,
                                                   exactFrame, vertex);
                          }},
               cfg.method);
}

Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height,
                                    bool exactFrame) {
    Image2D<MethodPixel> out;
    evaluateMethod(cfg, frags, tex, width, height, exactFrame, out);
    return out;
}

namespace {

// One single-threaded pass of a C++ method over the fragments (inputs rounded before).
template <class Real>
double cppPass(const BuiltinMethod& b, const MethodTextures& tex,
               const std::vector<Vec2<Real>>& uv0, const std::vector<Vec3<Real>>& view,
               const std::vector<Real>& lod) {
    double acc = 0;
    for (size_t k = 0; k < uv0.size(); ++k) {
        MethodContext<Real> c = makeMethodContext<Real>(tex);
        c.lod = lod[k];
        Vec2<Real> uv = runMethod<Real>(b, c, uv0[k], view[k]);
        acc += double(uv.x + uv.y);
    }
    return acc;
}

template <class Real>
std::vector<double> cppPasses(const MethodConfig& cfg, const BuiltinMethod& b,
                              const FragmentList& frags, const MethodTextures& tex, int repeats) {
    // The inputs rounded before the clock starts: the time is the method's alone.
    const auto uv0 = toFloat<Vec2<Real>>(frags.uv0);
    const auto view = toFloat<Vec3<Real>>(methodViews(cfg, frags, false));
    std::vector<Real> lod(frags.size());
    const bool reads = readsDerivatives(cfg, tex, frags);
    for (size_t k = 0; k < lod.size(); ++k) lod[k] = fragmentLod<Real>(reads, tex, frags, k);
    std::vector<double> samples;
    volatile double sink = 0;  // keeps the results alive so the loop is not optimised away
    for (int r = 0; r < repeats; ++r) {
        throwIfCancelled();
        auto t0 = Clock::now();
        sink = sink + cppPass<Real>(b, tex, uv0, view, lod);
        samples.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
                          double(frags.size()));
    }
    return samples;
}

}  // namespace

namespace {

MethodTiming timeShader(const MethodConfig& cfg, const GlslSpec& spec, const FragmentList& frags,
                        const MethodTextures& tex, const TimingSpec& timing,
                        const VertexOutputs* vertex) {
    GlslTimingPlan plan;
    plan.minFragments = timing.glFragments;
    plan.minGpuMs = std::isfinite(timing.glMinMs) ? timing.glMinMs
                    : glContext().software        ? kGlMinMsSoftware
                                                  : kGlMinMsHardware;
    plan.minRepeats = timing.repeats;
    const GlslTiming g =
        timeGlsl(spec, glslMaps(cfg, tex), glslInputs(cfg, frags, false, 0, 0, vertex), plan)
            .timing;
    MethodTiming t;
    t.median = g.nsPerPixel;
    t.p25 = g.p25;
    t.p75 = g.p75;
    t.repeats = g.repeats;
    t.fragments = g.fragments;
    return t;
}

MethodTiming timeBuiltin(const MethodConfig& cfg, const BuiltinMethod& b, const FragmentList& frags,
                         const MethodTextures& tex, const TimingSpec& timing) {
    std::vector<double> s = b.doublePrecision
                                ? cppPasses<double>(cfg, b, frags, tex, timing.repeats)
                                : cppPasses<float>(cfg, b, frags, tex, timing.repeats);
    MethodTiming t;
    t.repeats = int(s.size());
    t.median = percentile(s, 0.5);
    t.p25 = percentile(s, 0.25);
    t.p75 = percentile(s, 0.75);
    t.fragments = int64_t(frags.size());
    return t;
}

}  // namespace

MethodTiming timeMethod(const MethodConfig& cfg, const FragmentList& frags,
                        const MethodTextures& tex, const TimingSpec& spec,
                        const VertexOutputs* vertex) {
    // An engine vertex stage's outputs reach the timing workload at the fragments'
    // barycentrics; without them (or the barycentrics) the method is not timed.
    if (cfg.shader() && cfg.shader()->vertexStage() &&
        (!vertex || frags.bary.size() != frags.size() || frags.triangle.size() != frags.size()))
        return {};
    if (frags.size() == 0 || spec.repeats < 1) return {};
    return std::visit(
        Overloaded{[&](const BuiltinMethod& b) { return timeBuiltin(cfg, b, frags, tex, spec); },
                   [&](const ShaderMethod& m) {
                       return timeShader(cfg, *m.spec, frags, tex, spec, vertex);
                   }},
        cfg.method);
}

}  // namespace pgt
