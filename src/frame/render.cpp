// The frame pipeline in bands: raster -> truth -> methods -> comparison -> sinks, with stage
// timings.
#include "frame/render.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/memory.h"
#include "core/overloaded.h"
#include "evaluate/vertex_inputs.h"
#include "frame/truth_source.h"
#include "methods/config.h"
#include "truth/tessellation.h"

namespace pgt {

namespace {

// Where a view's truth and fragments come from: surfaces traced band by band, or whole frames
// traced before (block by block: renderFrame; once for many configurations: a
// PreparedView); fragments rasterised band by band, or prepared.
// The height map's lowest, highest and mean h.
struct HeightRange {
    float lo = INFINITY, hi = -INFINITY;
    double mean = 0.5;
};
HeightRange heightRange(const Texture& map) {
    HeightRange r;
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k < map.texels.size(); k += size_t(map.channels), ++n)
        r.lo = std::min(r.lo, map.texels[k]), r.hi = std::max(r.hi, map.texels[k]),
        sum += map.texels[k];
    if (n > 0) r.mean = sum / double(n);
    return r;
}

// What the warnings' checks need to know of a case (compare/warnings.h): the (s, b) the
// method is given, where the true relief lies (the map's range [lo, hi]), whether the map
// varies.
CheckContext checkContext(const HeightRange& range, int texelsPerUv, const MethodConfig& cfg,
                          const Displacement& d) {
    const float lo = range.lo, hi = range.hi;
    const auto [s, b] = cfg.scaleBias(d.scale, d.bias);
    CheckContext c;
    c.scale = d.scale, c.bias = d.bias, c.methodScale = s, c.methodBias = b;
    c.meanHeight = range.mean;
    c.texelsPerUv = texelsPerUv;
    c.displaced = s != 0 || b != 0;
    c.below =
        (d.scale != 0 || d.bias != 0) && d.scale * lo + d.bias <= 0 && d.scale * hi + d.bias <= 0;
    c.mapVaries = hi > lo;
    c.skipNoOffset = !readsDisplacement(cfg);
    c.userCode = variedAsShader(cfg);
    return c;
}

// One configuration across the bands: its maps, its tallies, the band's images.
struct MethodRun {
    const MethodConfig* config = nullptr;
    const MethodTextures* textures = nullptr;
    ErrorTally tally, tallyExact;
    // The per-vertex frame's error summed over the pixels with an exact frame (those the
    // exact pass counts), for the frame's share of the mean.
    double sumWhereExact = 0;
    int64_t countWhereExact = 0;
    MethodChecks checks;
    Image2D<MethodPixel> pixels;
    Image2D<float> errTexels;
    std::optional<VertexOutputs> vertex;  // its engine vertex stage's, where it has one
};

// The truth's depth offsets (docs/model.md §5b): where the rasteriser covers a pixel the truth
// hit, the hit's distance along the ray beyond the drawn point, in UV units (l world units).
void setTruthDepths(Image2D<TruthSample>& truth, const Image2D<Fragment>& frags, double l) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, truth.data.size(), 8192), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            TruthSample& t = truth.data[k];
            const Fragment& f = frags.data[k];
            t.depth = t.hit && f.covered ? (t.t - f.rayT) / l : NAN;
        }
    });
}

// Adds the band's truth hits and holes to the frame's counts.
void countHits(const Image2D<TruthSample>& truth, int64_t& hits, int64_t& holes) {
    using Counts = std::pair<int64_t, int64_t>;
    const Counts c = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, truth.data.size(), 8192), Counts{0, 0},
        [&](const auto& r, Counts acc) {
            for (size_t k = r.begin(); k < r.end(); ++k)
                acc.first += truth.data[k].hit, acc.second += truth.data[k].hole;
            return acc;
        },
        [](Counts a, const Counts& b) {
            return Counts{a.first + b.first, a.second + b.second};
        });
    hits += c.first, holes += c.second;
}

// A band image into rows [y0, y0 + its height) of `full`.
template <class T>
void copyRows(const Image2D<T>& band, int y0, Image2D<T>& full) {
    std::copy(band.data.begin(), band.data.end(), full.data.begin() + int64_t(y0) * full.width);
}

// The frame in bands: each stage of a band over all cores, then the next band.
static_assert(kBandRows % 2 == 0, "bands keep the GL's 2x2 quads whole (evaluateGlsl)");

class BandPipeline {
  public:
    BandPipeline(const Scene& scene, const TruthSource& truth,
                 const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                 const TimingSpec& timing, const FrameOptions& options, RenderResult& r)
        : scene_(scene),
          configs_(configs),
          truth_(truth),
          timing_(timing),
          options_(options),
          textures_(textures),
          r_(r),
          sampler_(timing.maxFragments, timing.seed) {
        const bool inPlace = options.keepImages || options.keepCodedErrors;
        const HeightRange range = heightRange(scene.height);  // once a frame, for every method
        for (const MethodConfig& cfg : configs) {
            MethodRun m;
            m.config = &cfg;
            if (inPlace) m.tally = ErrorTally(r.camera.width(), r.camera.height());
            m.textures = &textures.get(cfg, r.view.displacement);
            m.checks =
                MethodChecks(checkContext(range, scene.height.width, cfg, r.view.displacement));
            runs_.push_back(std::move(m));
        }
    }

    void run() {
        auto t0 = Clock::now();
        // The drawn mesh culled and binned, unless the fragments are prepared; the engine
        // vertex stages run on it.
        const bool vertexStages = std::any_of(runs_.begin(), runs_.end(), [](const MethodRun& m) {
            return hasVertexStage(*m.config);
        });
        const BaseMesh mesh =
            truth_.prepared() && !vertexStages ? BaseMesh{} : drawnBaseMesh(scene_.base, r_.camera);
        r_.timings.add(Stage::Raster, msSince(t0));
        t0 = Clock::now();
        if (vertexStages) {
            const VertexStageInputs in = vertexStageInputs(mesh, r_.camera);
            for (MethodRun& m : runs_)
                m.vertex = runMethodVertexStage(*m.config, in, m.textures->scale, m.textures->bias);
            r_.timings.add(Stage::VertexStage, msSince(t0));
            t0 = Clock::now();
        }
        std::optional<Rasterizer> raster;
        if (!truth_.prepared()) {
            const RasterOptions o = rasterOptions(scene_, r_.view, configs_);
            quadHelpers_ = o.quadHelpers;
            raster.emplace(mesh, r_.camera, o);
            r_.raster = raster->setupStats();
        }
        r_.timings.add(Stage::Raster, msSince(t0));
        const int W = r_.camera.width(), H = r_.camera.height();
        if (options_.keepImages) r_.truth = Image2D<TruthSample>(W, H);
        if (options_.keepImages) {
            r_.fragments = Image2D<Fragment>(W, H);
            for (size_t i = 0; i < runs_.size(); ++i) {
                r_.methods.emplace_back();
                r_.methods.back().pixels = Image2D<MethodPixel>(W, H);
                r_.methods.back().errTexels = Image2D<float>(W, H);
            }
        }
        const int rows = bandRows(W);
        for (int y0 = 0; y0 < H; y0 += rows) {
            throwIfCancelled();
            const PixelRect band{0, y0, W, std::min(H, y0 + rows)};
            rasterBand(raster ? &*raster : nullptr, band);
            traceBand(band);
            methodsBand(band.y0);
            emit(band);
        }
        finish();
    }

  private:
    // The band's fragments: rasterised, or the prepared view's.
    void rasterBand(const Rasterizer* raster, PixelRect band) {
        auto t0 = Clock::now();
        if (const PreparedView* prepared = truth_.prepared()) {
            const PreparedView::Band& b = prepared->bands[size_t(band.y0 / bandRows(band.width()))];
            fragments_ = &b.fragments;
            inputs_ = &b.inputs;
            frags_ = &b.frags;
        } else {
            raster->rasterizeRows(band.y0, band.y1, ownFragments_, r_.raster, &ownInputs_,
                                  &ownHelpers_);
            // Pixel indices within the band.
            compactFragments(ownFragments_, &ownInputs_, raster->options(), ownFrags_,
                             quadHelpers_ ? &ownHelpers_ : nullptr);
            fragments_ = &ownFragments_;
            inputs_ = &ownInputs_;
            frags_ = &ownFrags_;
        }
        if (timing_.repeats > 0) sampler_.add(*frags_);
        r_.timings.add(Stage::Raster, msSince(t0));
    }

    void traceBand(PixelRect band) {
        auto t0 = Clock::now();
        truthBand_ = &truth_.band(r_.camera, band, ownTruth_);
        if (!truth_.prepared()) setTruthDepths(ownTruth_, *fragments_, scene_.worldPerUv());
        countHits(*truthBand_, r_.truthHits, r_.truthHoles);
        r_.timings.add(Stage::Trace, msSince(t0));
        if (!truth_.haveFine()) return;
        auto t1 = Clock::now();
        truth_.fineBand(r_.camera, band, fineBand_);
        uncertainty_.add(*truthBand_, fineBand_, scene_.height.width, scene_.height.height,
                         scene_.height.address);
        r_.timings.add(Stage::TraceFine, msSince(t1));
    }

    // One configuration over the band's fragments (V in the exact frame or not) into `out`
    // (its storage reused from band to band).
    void evaluate(const MethodRun& m, bool exactFrame, Image2D<MethodPixel>& out) const {
        const int W = fragments_->width, H = fragments_->height;
        if (frags_->pixel.empty())  // nothing in this band
            out = Image2D<MethodPixel>(W, H);
        else
            evaluateMethod(*m.config, *frags_, *m.textures, W, H, exactFrame, out,
                           m.vertex ? &*m.vertex : nullptr);
    }

    // The band's GLSL methods drawn together, in one call of FrameOptions::glDraw when given
    // (a study's draw gate: one wait a band, not one a method); their exact-frame passes too.
    void drawGlsl(std::vector<Image2D<MethodPixel>>& exact) {
        auto draws = [&] {
            for (size_t i = 0; i < runs_.size(); ++i) {
                if (!runsInGl(*runs_[i].config)) continue;
                evaluate(runs_[i], false, runs_[i].pixels);
                if (framesCanDiffer(scene_.base)) evaluate(runs_[i], true, exact[i]);
            }
        };
        const bool any = std::any_of(runs_.begin(), runs_.end(),
                                     [](const MethodRun& m) { return runsInGl(*m.config); });
        if (!any || frags_->pixel.empty())
            draws();
        else if (options_.glDraw)
            options_.glDraw(draws);
        else
            draws();
    }

    // Every configuration over the band's fragments, compared with the band's truth.
    void methodsBand(int y0) {
        const Texture& map = scene_.height;
        auto tg = Clock::now();
        noneErrors(*frags_, *truthBand_, {map.width, map.height, map.address}, noneErrors_);
        r_.timings.add(Stage::Methods, msSince(tg));
        tg = Clock::now();
        std::vector<Image2D<MethodPixel>> glExact(runs_.size());
        drawGlsl(glExact);
        const Image2D<TruthSample>& exactTruth = truthWhereExact();
        r_.timings.add(Stage::MethodsEval, msSince(tg));
        r_.timings.add(Stage::Methods, msSince(tg));
        for (size_t i = 0; i < runs_.size(); ++i) {
            MethodRun& m = runs_[i];
            const bool gl = runsInGl(*m.config);
            auto t0 = Clock::now();
            if (!gl) evaluate(m, false, m.pixels);
            r_.timings.add(Stage::MethodsEval, msSince(t0));
            m.tally.add(*truthBand_, m.pixels, map.width, map.height, map.address, &m.errTexels,
                        y0);
            m.checks.add(*frags_, frags_->view, m.pixels, m.errTexels, noneErrors_);
            if (framesCanDiffer(scene_.base) && !frags_->pixel.empty()) {
                if (!gl) evaluate(m, true, exactPixels_);
                Image2D<MethodPixel>& exact = gl ? glExact[i] : exactPixels_;
                leaveOutNoExactFrame(exact, m);
                m.tallyExact.add(exactTruth, exact, map.width, map.height, map.address);
            }
            r_.timings.add(Stage::Methods, msSince(t0));
        }
    }

    // The band's truth for the exact pass: where a covered pixel's triangle has no exact frame
    // (zero UV area), its hit is left out, so the exact pass counts only pixels it defines.
    const Image2D<TruthSample>& truthWhereExact() {
        const Image2D<Fragment>& frags = *fragments_;
        const bool any = framesCanDiffer(scene_.base) &&
                         std::any_of(frags.data.begin(), frags.data.end(),
                                     [](const Fragment& f) { return f.covered && !f.exactFrame; });
        if (!any) return *truthBand_;
        truthWhereExact_ = *truthBand_;
        for (size_t k = 0; k < frags.data.size(); ++k)
            if (frags.data[k].covered && !frags.data[k].exactFrame)
                truthWhereExact_.data[k].hit = false;
        return truthWhereExact_;
    }

    // A method's exact-frame pixels without an exact frame left out (not covered: with the
    // truth's hit left out too, they count as neither), and its per-vertex error summed over
    // the rest.
    void leaveOutNoExactFrame(Image2D<MethodPixel>& exact, MethodRun& m) const {
        const Image2D<Fragment>& frags = *fragments_;
        for (size_t k = 0; k < frags.data.size(); ++k) {
            const Fragment& f = frags.data[k];
            if (!f.covered) continue;
            if (!f.exactFrame) {
                exact.data[k].covered = false;
                continue;
            }
            const float e = m.errTexels.data[k];
            if (std::isfinite(e)) m.sumWhereExact += e, ++m.countWhereExact;
        }
    }

    void emit(PixelRect band) {
        auto t0 = Clock::now();
        FrameBand fb{band.y0, band.y1, truthBand_, fragments_, {}, {}};
        fb.inputs = madeInputs();
        for (size_t i = 0; i < runs_.size(); ++i) {
            fb.pixels.push_back(&runs_[i].pixels);
            fb.errTexels.push_back(&runs_[i].errTexels);
            if (options_.keepImages) {
                copyRows(runs_[i].pixels, band.y0, r_.methods[i].pixels);
                copyRows(runs_[i].errTexels, band.y0, r_.methods[i].errTexels);
            }
        }
        if (options_.keepImages) copyRows(*truthBand_, band.y0, r_.truth);
        if (options_.keepImages) copyRows(*fragments_, band.y0, r_.fragments);
        if (options_.keepImages && madeInputs()) {
            if (r_.fragmentInputs.width != inputs_->width)
                r_.fragmentInputs = Image2D<FragmentInputs>(r_.camera.width(), r_.camera.height());
            copyRows(*inputs_, band.y0, r_.fragmentInputs);
        }
        for (FrameSink* sink : options_.sinks) sink->band(r_, fb);
        r_.timings.add(Stage::Write, msSince(t0));
    }

    // The statistics of the whole frame and each method's cost on the timing subset.
    void finish() {
        FragmentList timed = sampler_.take();
        r_.methods.resize(runs_.size());
        auto tStats = Clock::now();
        // The statistics (each method's percentiles over the frame, and the truth's
        // uncertainty) one per core.
        tbb::parallel_for(size_t(0), runs_.size() + 1, [&](size_t i) {
            if (i == runs_.size()) {
                if (!truth_.haveFine()) return;
                r_.uncertainty = uncertainty_.finish();
                r_.uncertainty.rate = scene_.truth.rate;
                r_.uncertainty.rateFine = 2 * scene_.truth.rate;
                r_.haveUncertainty = true;
                return;
            }
            MethodRun& m = runs_[i];
            MethodFrame& mf = r_.methods[i];
            mf.stats = m.tally.finish();
            mf.coded = m.tally.takeCoded();
            mf.warnings = m.checks.finish();
            if (framesCanDiffer(scene_.base)) {
                mf.statsExactFrame = m.tallyExact.finish();
                mf.haveExactFrame = true;
                mf.meanWhereExactFrame =
                    m.countWhereExact ? m.sumWhereExact / double(m.countWhereExact) : NAN;
            }
        });
        r_.timings.set(Stage::Statistics, msSince(tStats));
        auto t0 = Clock::now();
        for (size_t i = 0; i < runs_.size(); ++i) {
            MethodRun& m = runs_[i];
            MethodFrame& mf = r_.methods[i];
            mf.config = *m.config;
            mf.timingBackend = timingBackend(*m.config);
            mf.precomputeMs = textures_.precomputeMs(*m.config, r_.view.displacement);
            if (timing_.repeats > 0 && !options_.deferTiming) {
                mf.timing = timeMethod(*m.config, timed, *m.textures, timing_,
                                       m.vertex ? &*m.vertex : nullptr);
                mf.nsPerPixel = mf.timing.median;
            }
        }
        if (options_.deferTiming) r_.timed = std::move(timed);
        r_.timings.set(Stage::MethodTiming, msSince(t0));
    }

    // The band's FragmentInputs where the rasteriser made them (a method reads them), else null.
    // (Made for an engine vertex stage's barycentrics alone, they are not the frame's.)
    const Image2D<FragmentInputs>* madeInputs() const {
        return inputs_ && inputs_->width == fragments_->width && readsFragmentInputs(configs_)
                   ? inputs_
                   : nullptr;
    }

    const Scene& scene_;
    const std::vector<MethodConfig>& configs_;
    const TruthSource& truth_;
    const TimingSpec& timing_;
    bool quadHelpers_ = false;  // the raster makes its quads' helper lanes (a GL draw)
    const FrameOptions& options_;
    const MethodTextureCache& textures_;
    RenderResult& r_;
    FragmentSampler sampler_;
    std::vector<MethodRun> runs_;
    UncertaintyTally uncertainty_;
    // The current band.
    // The current band: its truth, fragments (as an image and as a list): what was traced and
    // rasterised here (own*), or a prepared view's.
    const Image2D<TruthSample>* truthBand_ = nullptr;
    const Image2D<Fragment>* fragments_ = nullptr;
    const Image2D<FragmentInputs>* inputs_ = nullptr;  // empty where no method reads them
    const FragmentList* frags_ = nullptr;
    Image2D<TruthSample> ownTruth_, fineBand_;
    Image2D<Fragment> ownFragments_;
    Image2D<FragmentInputs> ownInputs_;
    std::vector<HelperLane> ownHelpers_;
    FragmentList ownFrags_;
    Image2D<MethodPixel> exactPixels_;      // a built-in's pixels in the exact frame
    Image2D<TruthSample> truthWhereExact_;  // the truth for the exact pass (truthWhereExact)
    std::vector<float> noneErrors_;         // uv0's error at each of the band's fragments
};

RenderResult renderWith(const Scene& scene, const ViewSpec& view, const Camera& camera,
                        const TruthSource& truth, const std::vector<MethodConfig>& configs,
                        MethodTextureCache& textures, const TimingSpec& timing,
                        const FrameOptions& options) {
    RenderResult r;
    r.view = view;
    r.camera = camera;
    truth.describe(r);
    for (Stage stage :
         {Stage::Raster, Stage::Trace, Stage::Methods, Stage::MethodsEval, Stage::Write})
        r.timings.set(stage, 0);
    if (truth.haveFine()) r.timings.set(Stage::TraceFine, 0);
    BandPipeline(scene, truth, configs, textures, timing, options, r).run();
    return r;
}

}  // namespace

RasterOptions rasterOptions(const Scene& scene, const ViewSpec& view,
                            const std::vector<MethodConfig>& configs) {
    RasterOptions o{.cullBackFaces = scene.cullBackFaces,
                    .worldPerUv = scene.worldPerUv(),
                    .exactFrame = framesCanDiffer(scene.base),
                    .perVertexView = false,
                    .engineInputs = false,
                    .uvDerivatives = false,
                    .light = lightToward(view).value_or(Vec3d(0))};
    for (const MethodConfig& c : configs) {
        o.uvDerivatives = o.uvDerivatives || c.lodGrad || runsInGl(c);
        o.perVertexView = o.perVertexView || c.viewPerVertex;
        o.engineInputs = o.engineInputs || readsEngineInputs(c);
        o.quadHelpers = o.quadHelpers || runsInGl(c);
        o.barycentrics = o.barycentrics || hasVertexStage(c);
    }
    return o;
}

bool readsFragmentInputs(const std::vector<MethodConfig>& configs) {
    return std::any_of(configs.begin(), configs.end(), [](const MethodConfig& c) {
        return c.viewPerVertex || readsEngineInputs(c);
    });
}

PreparedView prepareView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                         const std::vector<MethodConfig>& configs) {
    PreparedView v;
    v.view = view;
    v.camera = makeCamera(scene, view);
    v.build = truths.truth->stats();
    const Image2D<TruthSample> truth =
        truths.truth->traceFrame(v.camera, TraceMode::Coherent, lightToward(view));
    Image2D<FragmentInputs> inputs;
    std::vector<HelperLane> helpers;
    const RasterOptions options = rasterOptions(scene, view, configs);
    const Image2D<Fragment> fragments = rasterize(drawnBaseMesh(scene.base, v.camera), v.camera,
                                                  options, &v.raster, &inputs, &helpers);
    const int W = v.camera.width(), H = v.camera.height(), R = bandRows(W);
    // Each band's helper lanes (bands keep quads whole; a lane below an odd frame is the last
    // band's), rows counted within the band.
    std::vector<std::vector<HelperLane>> bandHelpers(size_t((H + R - 1) / R));
    for (HelperLane& h : helpers) {
        const int band = std::min(h.at.y, H - 1) / R;
        h.at.y -= band * R;
        bandHelpers[size_t(band)].push_back(std::move(h));
    }
    for (int y0 = 0; y0 < H; y0 += R) {  // the pipeline's bands
        const int rows = std::min(H, y0 + R) - y0;
        PreparedView::Band b;
        const PixelRect band{0, y0, W, y0 + rows};
        b.truth = rowsOf(truth, band);
        b.fragments = rowsOf(fragments, band);
        if (inputs.width == W) b.inputs = rowsOf(inputs, band);
        compactFragments(b.fragments, &b.inputs, options, b.frags,
                         options.quadHelpers ? &bandHelpers[size_t(y0 / R)] : nullptr);
        setTruthDepths(b.truth, b.fragments, scene.worldPerUv());
        v.bands.push_back(std::move(b));
    }
    return v;
}

RenderResult renderPrepared(const Scene& scene, const PreparedView& v,
                            const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                            const FrameOptions& frame) {
    RenderResult r = renderWith(scene, v.view, v.camera, PreparedTruth(v), configs, textures,
                                TimingSpec{.repeats = 0}, frame);
    r.raster = v.raster;
    return r;
}

RenderResult renderView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                        const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                        const TimingSpec& timing, const FrameOptions& frame) {
    return renderWith(scene, view, makeCamera(scene, view),
                      SurfacesTruth(truths, lightToward(view)), configs, textures, timing, frame);
}

RenderResult renderFrame(const Scene& scene, const RenderOptions& options) {
    const Camera camera = makeCamera(scene);
    const std::optional<Vec3d> light = lightToward(scene.view());
    MethodTextureCache textures(scene.height, scene.uvExtent);
    const TimingSpec timing{.repeats = options.timingRepeats,
                            .maxFragments = options.timingFragments,
                            .seed = 1,
                            .glFragments = options.glTimingFragments};
    auto t0 = Clock::now();
    if (scene.plane()) {
        // A block's lattice: truth.memory_mb, or what the memory limit leaves beside the rest
        // of the view when that is less.
        constexpr double kMiB = 1024.0 * 1024.0;
        const double beside =
            bytesBesideTruth(scene, camera, !options.frame.sinks.empty(), options.frame.keepImages);
        const double budget = std::max(0.0, std::min(double(scene.truth.memoryMb) * kMiB,
                                                     double(memoryLimitMb()) * kMiB - beside)) /
                              kTruthBytesPerGridVertex;
        // What the frame's truth builds (frameWindow: a grazing view of an infinite plane
        // walks its tile, whatever area the view spans).
        const double vertices = truthVertices(scene, camera, light);
        TruthFrames f;
        const bool blocks =
            vertices > budget && traceTruthInBlocks(scene, camera, light, budget, f);
        if (vertices > budget && !blocks)  // no split into at most 16 x 16 blocks fits
            checkMemory(vertices * kTruthBytesPerGridVertex + beside, scene.file, "truth.memory_mb",
                        std::to_string(scene.truth.memoryMb),
                        "the view's truth lattice (" + std::to_string(int64_t(vertices)) +
                            " vertices; no split of the frame into at most 16 x 16 blocks "
                            "brings a block under the budget) beside the rest of the frame");
        if (blocks) {
            double truthMs = msSince(t0);
            RenderResult r = renderWith(scene, scene.view(), camera, FramesTruth(f), scene.methods,
                                        textures, timing, options.frame);
            r.timings.set(Stage::Trace, f.traceMs);
            if (f.haveFine) r.timings.set(Stage::TraceFine, f.fineMs);
            r.timings.set(Stage::TruthTotal, truthMs);
            return r;
        }
    }
    TruthBuilder builder(scene);
    builder.limitToView(camera, light, scene.displacement);
    TruthPair truths = builder.build(scene.displacement, scene.truth.uncertainty);
    double buildMs = msSince(t0);
    RenderResult r =
        renderView(scene, scene.view(), truths, scene.methods, textures, timing, options.frame);
    r.timings.set(Stage::Tessellate, r.truthBuild.tessellateMs);
    r.timings.set(Stage::Build, r.truthBuild.buildMs);
    if (truths.fine) {
        r.timings.set(Stage::TessellateFine, r.truthBuildFine.tessellateMs);
        r.timings.set(Stage::BuildFine, r.truthBuildFine.buildMs);
    }
    r.timings.set(Stage::TruthTotal, buildMs);
    return r;
}

}  // namespace pgt
