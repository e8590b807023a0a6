// One frame end to end: truth (two rates for its uncertainty), rasterisation, every method,
// comparison. What `pgt render` runs; sweeps (later) reuse the stages one by one.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compare/compare.h"
#include "core/image.h"
#include "heightfield/heightfield.h"
#include "raster/raster.h"
#include "scene/scene.h"
#include "truth/truth.h"

namespace pgt {

// The rasterised fragments in compact form, what the method kernels consume.
struct FragmentList {
    std::vector<int32_t> pixel;  // y * width + x
    std::vector<Vec2f> uv0;
    std::vector<Vec3f> view;     // unit tangent-space V
    std::vector<Vec2d> uv0d;     // double copies for `precision: double`
    std::vector<Vec3d> viewd;
};
FragmentList compactFragments(const Image2D<Fragment>& frags);

// Inputs every method needs for one (scale, bias): the height map and, when asked for,
// 003's derived maps.
struct MethodTextures {
    const Texture* height = nullptr;
    std::unique_ptr<DerivedMaps> derived;  // only when a method needs them
    double scale = 0, bias = 0, tiling = 1;
};
MethodTextures makeMethodTextures(const Texture& height, double scale, double bias,
                                  double tiling, bool needDerived);

// Runs one method over all fragments (all cores); pixels not in the list stay uncovered.
Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height);

// Measured cost of the method alone: single-threaded, median of `repeats` passes over the
// fragment list, in nanoseconds per fragment.
double timeMethodNsPerPixel(const MethodConfig& cfg, const FragmentList& frags,
                            const MethodTextures& tex, int repeats);

struct MethodFrame {
    MethodConfig config;
    Image2D<MethodPixel> pixels;
    Image2D<float> errTexels;
    FrameStats stats;
    double nsPerPixel = 0;
};

struct RenderOptions {
    int timingRepeats = 3;
};

struct RenderResult {
    Camera camera;
    Image2D<TruthSample> truth;
    Image2D<Fragment> fragments;
    TruthBuildStats truthBuild, truthBuildFine;
    TruthUncertainty uncertainty;
    bool haveUncertainty = false;
    RasterStats raster;
    std::vector<MethodFrame> methods;
    std::map<std::string, double> timingsMs;  // stage -> wall ms
};

RenderResult renderFrame(const Scene& scene, const RenderOptions& options = {});

}  // namespace pgt
