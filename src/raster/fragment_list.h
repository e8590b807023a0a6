// The rasterised fragments in compact form (one entry per covered pixel), what the method
// kernels and the GL runner consume, and a seeded subset of them for timing.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "raster/raster.h"

namespace pgt {

// In double, as the rasteriser made them: a float method (and the GL) rounds uv0 and V to
// float when it reads them, exactly once, as a GPU's varyings are; `precision: double`
// reads them as they are. 44 bytes per fragment on a plane without a light, where no method
// reads uv0's derivatives; 148 with all of them, 272 with the FragmentInputs (4 more with the
// triangles of a GL draw on the screen, and its helper lanes).
struct FragmentList {
    std::vector<int32_t> pixel;  // y * width + x
    std::vector<Vec2d> uv0;
    std::vector<Vec3d> view;  // unit tangent-space V (Lengyel FGED 2 Listing 7.8's frame)
    // V in the exact frame of the drawn surface (meshes; empty where the raster did not make
    // it: it is `view` there, viewExactAt).
    std::vector<Vec3d> viewExact;
    // uv0's screen derivatives (Fragment::uvDx, uvDy); empty where no method of the frame
    // reads them (RasterOptions::uvDerivatives).
    std::vector<Vec2d> uvDx, uvDy;
    std::vector<Vec3d> light, lightExact;  // the light in each frame (Fragment::lightTangent)
    std::vector<Vec3d> viewVertex;         // V per vertex, interpolated (Fragment)
    std::vector<EngineInputs> engine;      // an engine's varyings (Fragment::engine)
    std::vector<Vec3d> bary;               // FragmentInputs::bary (with the inputs)
    // For a GL draw on the screen (RasterOptions::quadHelpers; else both empty): each
    // fragment's triangle (Fragment::triangle) and the helper lanes of their quads.
    std::vector<uint32_t> triangle;
    std::vector<HelperLane> helpers;
    size_t size() const { return pixel.size(); }
    // Fragment k's per-vertex V and engine inputs; a list made by hand (tests) that left them
    // out gives the per-pixel V and zero inputs.
    Vec3d viewVertexAt(size_t k) const { return k < viewVertex.size() ? viewVertex[k] : view[k]; }
    Vec3d viewExactAt(size_t k) const { return k < viewExact.size() ? viewExact[k] : view[k]; }
    bool hasDerivatives() const { return uvDx.size() == size() && uvDy.size() == size(); }
    EngineInputs engineAt(size_t k) const { return k < engine.size() ? engine[k] : EngineInputs{}; }
    // Fragment k's light in either frame; zero (no light) where a list made by hand (tests)
    // left the lights out.
    Vec3d lightAt(size_t k, bool exactFrame = false) const {
        const std::vector<Vec3d>& l = exactFrame ? lightExact : light;
        return k < l.size() ? l[k] : Vec3d(0);
    }
    // Appends `from`'s fragments, their pixel indices moved by `pixelOffset` (their triangles,
    // barycentrics and helper lanes left out: lists joined this way are packed).
    void append(const FragmentList& from, int32_t pixelOffset = 0);
};
// The covered pixels of `frags`, row by row (pixel = y * width + x of that image); their
// per-vertex V and engine inputs from `inputs` where given (else those lists stay empty); with
// `helpers` (the raster's, moved in), their triangles too.
FragmentList compactFragments(const Image2D<Fragment>& frags,
                              const Image2D<FragmentInputs>* inputs = nullptr,
                              std::vector<HelperLane>* helpers = nullptr);
// The same into `list`, reusing its storage (a frame's bands), with only what the raster
// made by `made`: its lights left out (lightAt: zero) without a light, V in the exact frame
// without RasterOptions::exactFrame (viewExactAt: V) and uv0's derivatives without
// RasterOptions::uvDerivatives.
void compactFragments(const Image2D<Fragment>& frags, const Image2D<FragmentInputs>* inputs,
                      const RasterOptions& made, FragmentList& list,
                      std::vector<HelperLane>* helpers = nullptr);

// A seeded random subset of at most `count` fragments of lists added one after another
// (reservoir sampling: the same subset for the same fragments in the same order, however
// they were split into lists; each fragment kept with probability count / n). All of them
// when count <= 0. Triangles and barycentrics are kept where the lists have both (an engine
// vertex stage's outputs are read there); helper lanes are not.
class FragmentSampler {
  public:
    FragmentSampler(int count, uint32_t seed) : count_(count), rng_(seed) {}
    void add(const FragmentList& list);
    // The subset, in the order the fragments were added (the scan order's memory locality).
    FragmentList take();

  private:
    double uniform();
    void skip();  // draws next_, the next fragment to enter the full reservoir
    int count_;
    std::mt19937_64 rng_;
    int64_t seen_ = 0;
    int64_t next_ = 0;
    double w_ = 1;
    FragmentList kept_;
    std::vector<int64_t> order_;  // position of each kept fragment among those added
};

// One list's subset (FragmentSampler).
FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed);

}  // namespace pgt
