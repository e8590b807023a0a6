// One view end to end: truth (truth/builder.h, two rates for its uncertainty), rasterisation
// (raster/), every method (study/evaluate.h), comparison (compare/). `pgt render` runs one;
// studies (study/sweep.h) run many, reusing the truth per (s, b) and the method textures,
// which is why the pieces are separate.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compare/compare.h"
#include "compare/uncertainty.h"
#include "core/image.h"
#include "heightfield/heightfield.h"
#include "raster/fragment_list.h"
#include "raster/raster.h"
#include "scene/scene.h"
#include "study/evaluate.h"
#include "truth/builder.h"
#include "truth/truth.h"

namespace pgt {

struct MethodFrame {
    MethodConfig config;
    Image2D<MethodPixel> pixels;
    Image2D<float> errTexels;
    FrameStats stats;
    // Meshes: the same method fed the exact frame; the difference to `stats` is the share
    // of the error caused by the per-vertex tangent frame.
    FrameStats statsExactFrame;
    bool haveExactFrame = false;
    double nsPerPixel = 0;
    std::string timingBackend;  // "cpu", or "gl: RENDERER" for GLSL methods
};

struct RenderResult {
    ViewSpec view;  // the camera and (s, b) the frame was rendered with
    Camera camera;
    Image2D<TruthSample> truth;
    Image2D<Fragment> fragments;
    TruthBuildStats truthBuild, truthBuildFine;
    TruthUncertainty uncertainty;
    bool haveUncertainty = false;
    RasterStats raster;
    std::vector<MethodFrame> methods;
    std::map<std::string, double> timingsMs;  // stage -> wall ms
    int truthBlocks = 1;  // > 1: the truth was traced block by block (TruthSpec::memoryMb)
};

// The per-view measurement: one view with given truth surfaces (built for the view's (s, b)):
// truth frames, rasterisation, every method and its comparison; methods use the view's
// (s, b) unless they have their own. `keepImages` = false drops per-pixel images once the
// statistics are taken.
RenderResult renderView(const Scene& scene, const ViewSpec& view, const TruthPair& truths,
                        const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                        const TimingSpec& timing, bool keepImages = true);

struct RenderOptions {
    int timingRepeats = 3;
};

// The whole `pgt render`: builds the truth for the scene's (s, b) and renders its view.
RenderResult renderFrame(const Scene& scene, const RenderOptions& options = {});

// Memory one view needs, estimated before anything is allocated (bytes): the truth frames
// (two rates), the rasteriser's frame, the fragment list, each method's images and, when
// `writesImages`, the EXR and PNG being encoded; plus the truth geometry (a plane's lattice
// at the scene's rate and 2x, capped by truth.memory_mb when the frame may be traced in
// blocks). Throws InputError naming `field` when it exceeds the memory limit (core/memory.h).
double estimateViewBytes(const Scene& scene, int width, int height, size_t methods,
                         bool writesImages, bool truthInBlocks);
void checkViewMemory(const Scene& scene, int width, int height, size_t methods, bool writesImages,
                     bool truthInBlocks, const std::string& field);

// The base mesh the rasteriser draws for a scene and camera (an infinite plane is extended
// by whole tiles to cover the view).
BaseMesh sceneBaseMesh(const Scene& scene, const Camera& camera);

}  // namespace pgt
