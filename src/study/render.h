// One view end to end: truth (two rates for its uncertainty), rasterisation, every method,
// comparison. `pgt render` runs one; studies (study/sweep.h) run many, reusing the truth per
// (s, b) and the method textures, which is why the pieces are separate.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compare/compare.h"
#include "compare/uncertainty.h"
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
    std::vector<Vec3f> view;  // unit tangent-space V, rounded to float
    std::vector<Vec2d> uv0d;  // double copies for `precision: double`
    std::vector<Vec3d> viewd;
    std::vector<Vec3f> viewExact;  // V in the exact frame of the drawn surface (meshes)
    std::vector<Vec3d> viewExactd;
    size_t size() const { return pixel.size(); }
};
FragmentList compactFragments(const Image2D<Fragment>& frags);
// A seeded random subset of at most `count` fragments (all when count <= 0 or larger).
FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed);

// Inputs every method needs for one (s, b): the height map and, when asked for, 003's maps.
struct MethodTextures {
    const Texture* height = nullptr;
    std::unique_ptr<DerivedMaps> derived;  // only when a method needs them
    double scale = 0, bias = 0;
    UvExtent uvExtent;  // the base's UV range (discard_outside)
};
MethodTextures makeMethodTextures(const Texture& height, double scale, double bias,
                                  const UvExtent& uvExtent, bool needDerived);

// Method textures by (s, b), built on first use: the truth's (s, b) and any method's own.
class MethodTextureCache {
  public:
    MethodTextureCache(const Texture& height, const UvExtent& uvExtent)
        : height_(height), uvExtent_(uvExtent) {}
    const MethodTextures& get(double scale, double bias, bool needDerived);
    // Drops every entry (a study moving to the next (s, b): its derived maps are W x H x 16
    // bytes each, so keeping every (s, b) would grow with the study).
    void clear() { cache_.clear(); }

  private:
    const Texture& height_;
    UvExtent uvExtent_;
    std::map<std::pair<double, double>, MethodTextures> cache_;
};

// Runs one method over all fragments (all cores); pixels not in the list stay uncovered.
// `exactFrame` feeds V in the exact frame instead of the per-vertex (Listing 7.4/7.8) frame.
Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height,
                                    bool exactFrame = false);

// Measured cost of the method alone: single-threaded, median of `repeats` passes over the
// fragment list, in nanoseconds per fragment.
double timeMethodNsPerPixel(const MethodConfig& cfg, const FragmentList& frags,
                            const MethodTextures& tex, int repeats);

struct TimingSpec {
    int repeats = 3;       // median of this many single-threaded passes
    int maxFragments = 0;  // time a seeded subset of this many fragments (0 = all)
    uint32_t seed = 1;
};

// The truth surfaces of one (s, b): at the scene's rate and, for the uncertainty, at 2 x rate.
struct TruthPair {
    std::unique_ptr<TruthSurface> truth, fine;
};

// Base tessellations (independent of s, b) built once, displaced per (s, b) on request.
class TruthBuilder {
  public:
    explicit TruthBuilder(const Scene& scene) : scene_(scene) {}
    // New surfaces for (s, b).
    TruthPair build(const Displacement& disp, bool withUncertainty);
    // The builder's own surfaces re-displaced to (s, b) (TruthSurface::setDisplacement: no
    // reallocation, refit where it is faster); built on first use. Valid until the next call.
    const TruthPair& update(const Displacement& disp, bool withUncertainty);
    // Planes: tessellate only the part of the plane this view can see at (s, b) (large maps
    // framed closely). Call before the first build.
    void limitToView(const Camera& camera, const Displacement& disp, PixelRect block = {});
    const TruthWindow& window() const { return window_; }

  private:
    std::shared_ptr<const BaseTessellation> tessellate(int rate) const;
    const Scene& scene_;
    std::shared_ptr<const BaseTessellation> base_, fine_;
    TruthPair current_;
    TruthWindow window_;
};

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

// Where a method's ns/px comes from: "cpu" (single thread) or "gl: <GL_RENDERER>".
std::string timingBackend(const MethodConfig& cfg);

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
    int truthBlocks = 1;  // > 1: the truth was traced block by block (TruthSpec::memoryMb)
};

// The truth frames of one view (the fine one only with the uncertainty).
struct TruthFrames {
    Image2D<TruthSample> truth, fine;
    bool haveFine = false;
    TruthBuildStats build, buildFine;
    double traceMs = 0, fineMs = 0;
    int blocks = 1;  // > 1: traced block by block over windows (renderFrame)
};
TruthFrames traceTruth(const Camera& camera, const TruthPair& truths);

// Rasterisation, methods and comparison against given truth frames.
RenderResult renderWithTruth(const Scene& scene, const Camera& camera, TruthFrames&& truth,
                             const std::vector<MethodConfig>& configs, MethodTextureCache& textures,
                             const TimingSpec& timing, bool keepImages = true);

// One view with given truth surfaces; methods use the scene's (s, b) unless they have their
// own. `keepImages` = false drops per-pixel images once the statistics are taken.
RenderResult renderView(const Scene& scene, const Camera& camera, const TruthPair& truths,
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
