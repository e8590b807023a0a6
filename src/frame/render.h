// One view end to end: truth (truth/builder.h, two rates for its uncertainty), rasterisation
// (raster/), every method (evaluate/evaluate.h), comparison (compare/). `pgt render` runs
// one; studies (study/sweep.h) run many, reusing the truth per (s, b) and the method textures,
// which is why the pieces are separate.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compare/compare.h"
#include "compare/uncertainty.h"
#include "compare/warnings.h"
#include "core/clock.h"
#include "core/image.h"
#include "evaluate/evaluate.h"
#include "frame/view_memory.h"
#include "heightfield/heightfield.h"
#include "raster/fragment_list.h"
#include "raster/raster.h"
#include "scene/scene.h"
#include "truth/builder.h"
#include "truth/truth.h"

namespace pgt {

struct MethodFrame {
    MethodConfig config;
    Image2D<MethodPixel> pixels;  // kept images only (keepImages)
    Image2D<float> errTexels;     // kept images only
    // Kept images or FrameOptions::keepCodedErrors: each pixel's error in texels or the code
    // of why it has none (compare.h codedError), what the error maps are drawn from.
    Image2D<float> coded;
    FrameStats stats;
    // Meshes: the same method fed the exact frame; the difference to `stats` is the share
    // of the error caused by the per-vertex tangent frame.
    // Meshes: the error with V in the exact frame, over the pixels whose triangle has one
    // (not those of zero UV area), and the per-vertex frame's mean over the same pixels.
    FrameStats statsExactFrame;
    bool haveExactFrame = false;
    double meanWhereExactFrame = NAN;
    double nsPerPixel = NAN;  // timing.median; NaN when not measured
    MethodTiming timing;      // its spread, repeats and workload
    // A study's GLSL methods are timed once per view direction (docs/studies.md): the case
    // whose fragments and (s, b) the timing ran on; -1: this frame's own.
    int timingCase = -1;
    // The build time of its precomputed maps (the min-max pyramid, cone maps; methods/maps.h):
    // once per map, shared by every view and (s, b) of a run; 0 for methods without any.
    double precomputeMs = 0;
    // "cpu", or for GLSL methods "gl timer query: RENDERER" or "gl wall clock: RENDERER
    // (software renderer, not a GPU time)" (evaluate/evaluate.h timingBackend).
    std::string timingBackend;
    // Silent mistakes its output shows on this frame (compare/warnings.h).
    std::vector<MethodWarning> warnings;
};

// The share of a mesh's mean error that the per-vertex tangent frame adds: 1 - the exact
// frame's mean / the per-vertex frame's mean, both over the pixels with an exact frame; NaN
// where either is not finite or the mean is 0 (docs/outputs.md).
inline double frameShareOfMean(const MethodFrame& m) {
    const double a = m.meanWhereExactFrame, e = m.statsExactFrame.error.mean;
    return a > 0 && std::isfinite(a) && std::isfinite(e) ? 1.0 - e / a : NAN;
}

struct RenderResult {
    ViewSpec view;  // the camera and (s, b) the frame was rendered with
    Camera camera;
    Image2D<TruthSample> truth;              // kept images only
    Image2D<Fragment> fragments;             // kept images only
    Image2D<FragmentInputs> fragmentInputs;  // kept images, where a method read them
    TruthBuildStats truthBuild, truthBuildFine;
    TruthUncertainty uncertainty;
    bool haveUncertainty = false;
    RasterStats raster;
    std::vector<MethodFrame> methods;
    StageTimes timings;      // wall ms per stage, summed over the bands
    FragmentList timed;      // FrameOptions::deferTiming: the seeded subset to time methods on
    int64_t truthHits = 0;   // pixels whose truth ray hit the surface
    int64_t truthHoles = 0;  // misses where a plane's sheet had to be hit (TruthSample::hole)
    int truthBlocks = 1;     // > 1: the truth was traced block by block (TruthSpec::memoryMb)
};

// The frame is made in bands of rows (bandRows, the last one shorter): each band is
// rasterised, traced, evaluated and compared over all cores, handed to the sinks, and
// dropped, so memory follows the band, not the frame. A band has at least kBandRows rows
// and, in narrow frames, enough rows for kBandPixels pixels (a study's 96^2 frame is one band:
// one GL draw per method, not two); always an even count, so that the GL's 2x2 quads stay
// whole.
constexpr int kBandRows = 64, kBandPixels = 16384;
inline int bandRows(int width) {
    return std::max(kBandRows, (kBandPixels / std::max(width, 1)) & ~1);
}

// One band's images, each W x (y1 - y0), row y of the frame at row y - y0.
struct FrameBand {
    int y0 = 0, y1 = 0;
    const Image2D<TruthSample>* truth = nullptr;
    const Image2D<Fragment>* fragments = nullptr;
    std::vector<const Image2D<MethodPixel>*> pixels;  // per configuration
    std::vector<const Image2D<float>*> errTexels;     // per configuration; NaN: no error
    // V per vertex and an engine's inputs, where the frame's methods read them
    // (readsFragmentInputs); null otherwise.
    const Image2D<FragmentInputs>* inputs = nullptr;
};

// What consumes bands as they are made (in row order): the EXR stream, the error maps.
class FrameSink {
  public:
    virtual ~FrameSink() = default;
    virtual void band(const RenderResult& frame, const FrameBand& band) = 0;
};

struct FrameOptions {
    bool keepImages = true;              // assemble the whole frame's images in the result
    std::vector<FrameSink*> sinks = {};  // get every band
    bool keepCodedErrors = false;        // MethodFrame::coded (4 bytes a pixel per method)
    // Leave the methods' timing to timeMethods (RenderResult::timed keeps the subset):
    // a study times them in a phase of its own, where no rendering competes for the cores.
    bool deferTiming = false;
    // How each GLSL draw runs (a band's fragments at a time, as for every method): directly
    // when empty; a study runs them through its draw gate, so that no C++ timing runs beside
    // them (study/study_cases.cpp).
    std::function<void(const std::function<void()>&)> glDraw = {};
};

// The per-view measurement: one view with given truth surfaces (built for the view's (s, b)):
// truth, rasterisation, every method and its comparison; methods use the view's (s, b)
// unless they have their own.
RenderResult renderView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                        const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                        const TimingSpec& timing, const FrameOptions& frame = {});

// The C++ methods of a deferred-timing result timed on its subset (single-threaded each, the
// median of timing.repeats); GLSL methods were timed with their draws. Drops the subset.
// `textures` must hold every method's maps already (the render got them).
// `glsl` false leaves GLSL methods untimed (a study times them once per view direction).
void timeMethods(RenderResult& r, const MethodTextureCache& textures, const TimingSpec& timing,
                 bool glsl = true);

// The seeded subset of a view's fragments that its methods are timed on: the same subset a
// render of the view times (FragmentSampler), without tracing or evaluating anything.
FragmentList viewTimingFragments(const Scene& scene, const ViewSpec& view,
                                 const TimingSpec& timing);
// The outputs of `cfg`'s engine vertex stage in a view at (s, b), which its timing on
// viewTimingFragments reads; none where it has no vertex stage.
std::optional<VertexOutputs> viewVertexOutputs(const Scene& scene, const ViewSpec& view,
                                               const MethodConfig& cfg, double scale, double bias);

// A view traced and rasterised once, then measured for any number of configurations (pgt
// fit's candidates) by the same pipeline as renderView, its truth and fragments copied band by
// band instead of traced and rasterised (no uncertainty, no timing).
struct PreparedView {
    ViewSpec view;
    Camera camera;
    TruthBuildStats build;
    RasterStats raster;
    struct Band {  // the pipeline's bands of kBandRows rows
        Image2D<TruthSample> truth;
        Image2D<Fragment> fragments;
        Image2D<FragmentInputs> inputs;  // empty where no method reads them
        FragmentList frags;              // compactFragments(fragments, inputs)
    };
    std::vector<Band> bands;
};
// Rasterised for `configs` (rasterOptions): the configurations it will measure.
PreparedView prepareView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                         const std::vector<MethodConfig>& configs);

// What the rasteriser computes for these configurations (RasterOptions): V in the exact frame
// where the base's frames can differ from it, V per vertex and an engine's inputs where a
// configuration reads them, uv0's derivatives where one has "lod": "grad" or runs in GL;
// nothing else per pixel; the view's light.
RasterOptions rasterOptions(const Scene& scene, const ViewSpec& view,
                            const std::vector<MethodConfig>& configs);
// Whether any of them reads V per vertex or an engine's inputs (the rasteriser then makes
// FragmentInputs, and frame.exr gets base.Vvertex).
bool readsFragmentInputs(const std::vector<MethodConfig>& configs);
RenderResult renderPrepared(const Scene& scene, const PreparedView& view,
                            const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                            const FrameOptions& frame = {});

struct RenderOptions {
    int timingRepeats = 3;                // 0: no timing
    int timingFragments = 65536;          // a seeded subset of this many (0: every fragment)
    int64_t glTimingFragments = 1 << 20;  // GL: the subset repeated to this many per draw
    FrameOptions frame = {};
};

// The whole `pgt render`: builds the truth for the scene's (s, b) and renders its view.
RenderResult renderFrame(const Scene& scene, const RenderOptions& options = {});

}  // namespace pgt
