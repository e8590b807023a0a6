// Methods' timing apart from a frame's evaluation (frame/render.h: timeMethods, the timing
// subset of a view and its engine vertex stages' outputs).
#include <optional>

#include "core/clock.h"
#include "evaluate/vertex_inputs.h"
#include "frame/render.h"

namespace pgt {

void timeMethods(RenderResult& r, const MethodTextureCache& textures, const TimingSpec& timing,
                 bool glsl) {
    auto t0 = Clock::now();
    for (MethodFrame& mf : r.methods) {
        const MethodConfig& cfg = mf.config;
        if (timing.repeats <= 0 || (!glsl && runsInGl(cfg))) continue;
        mf.timing = timeMethod(cfg, r.timed, textures.at(cfg, r.view.displacement), timing);
        mf.nsPerPixel = mf.timing.median;
    }
    r.timed = {};
    r.timings.add(Stage::MethodTiming, msSince(t0));
}

FragmentList viewTimingFragments(const Scene& scene, const ViewSpec& view,
                                 const TimingSpec& timing) {
    const Camera camera = makeCamera(scene, view);
    Image2D<FragmentInputs> inputs;
    const RasterOptions options = rasterOptions(scene, view, scene.methods);
    const Image2D<Fragment> frame =
        rasterize(drawnBaseMesh(scene.base, camera), camera, options, nullptr, &inputs);
    // With an engine vertex stage, the triangles (its outputs are read there; no helper lanes).
    std::vector<HelperLane> noHelpers;
    FragmentList all;
    compactFragments(frame, &inputs, options, all, options.barycentrics ? &noHelpers : nullptr);
    return sampleFragments(all, timing.maxFragments, timing.seed);
}

std::optional<VertexOutputs> viewVertexOutputs(const Scene& scene, const ViewSpec& view,
                                               const MethodConfig& cfg, double scale, double bias) {
    if (!hasVertexStage(cfg)) return std::nullopt;
    const Camera camera = makeCamera(scene, view);
    return runMethodVertexStage(cfg, vertexStageInputs(drawnBaseMesh(scene.base, camera), camera),
                                scale, bias);
}

}  // namespace pgt
