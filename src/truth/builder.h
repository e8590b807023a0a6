// The truth of a scene for any (s, b): base tessellations built once per rate, displaced per
// (s, b) on request, traced over a view (whole, or block by block over windows of a plane
// when the whole view's truth would exceed truth.memory_mb).
#pragma once

#include <memory>

#include "core/image.h"
#include "core/samples.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "truth/truth.h"

namespace pgt {

// The truth surfaces of one (s, b): at the scene's rate and, for the uncertainty, at 2 x rate.
struct TruthPair {
    std::unique_ptr<TruthSurface> truth, fine;
};

// Base tessellations (independent of s, b) built once, displaced per (s, b) on request.
class TruthBuilder {
  public:
    // `height`: the scene's map shared instead of copied into each tessellation (a caller
    // whose tessellations end before the scene does may pass the scene's own, unowned).
    explicit TruthBuilder(const Scene& scene, std::shared_ptr<const Texture> height = nullptr)
        : scene_(scene), height_(std::move(height)) {}
    // New surfaces for (s, b).
    TruthPair build(const Displacement& disp, bool withUncertainty);
    // The builder's own surfaces re-displaced to (s, b) (TruthSurface::setDisplacement: no
    // reallocation, refit where it is faster); built on first use. Valid until the next call.
    const TruthPair& update(const Displacement& disp, bool withUncertainty);
    // Planes: tessellate only the part of the plane this view can see at (s, b) (large maps
    // framed closely), the finer pass over a window twice as wide (frameWindow's reach 2).
    // Call before the first build.
    void limitToView(const Camera& camera, const std::optional<Vec3d>& light,
                     const Displacement& disp, PixelRect block = {},
                     const TexelRange* range = nullptr);
    const TruthWindow& window() const { return window_; }

  private:
    std::shared_ptr<const BaseTessellation> tessellate(int rate, const TruthWindow& window) const;
    const Scene& scene_;
    std::shared_ptr<const Texture> height_;
    std::shared_ptr<const BaseTessellation> base_, fine_;
    TruthPair current_;
    TruthWindow window_, windowFine_;
};

// The truth frames of a view traced block by block before the frame is made (the fine one
// only with the uncertainty).
struct TruthFrames {
    Image2D<TruthSample> truth, fine;
    bool haveFine = false;
    TruthBuildStats build, buildFine;
    double traceMs = 0, fineMs = 0;
    int blocks = 1;  // > 1: traced block by block over windows (renderFrame)
};

// Plane vertices of a truth over the whole tile or `window`, and of its 2x-rate twin over
// `fine` when the scene asks for its uncertainty: the one count the memory budget and the
// blocks use.
double truthVertices(const Scene& scene, const TruthWindow& window, const TruthWindow& fine);
// The same for the windows a frame (or a block of it) builds: frameWindow at reach 1 and 2.
double truthVertices(const Scene& scene, const Camera& camera, const std::optional<Vec3d>& light,
                     PixelRect block = {}, const TexelRange* range = nullptr);

// The view's truth traced in n x n pixel blocks, each over a tessellation of only what the
// block sees, so peak memory is one block's. Returns false (frames untouched) when no
// n <= 16 brings every block under `budgetVertices`.
bool traceTruthInBlocks(const Scene& scene, const Camera& camera, const std::optional<Vec3d>& light,
                        double budgetVertices, TruthFrames& frames);

}  // namespace pgt
