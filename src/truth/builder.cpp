// TruthBuilder, traceTruth and block tracing (truth/builder.h).
#include "truth/builder.h"

#include <algorithm>
#include <vector>

#include "core/clock.h"
#include "core/error.h"
#include "core/overloaded.h"

namespace pgt {

std::shared_ptr<const BaseTessellation> TruthBuilder::tessellate(int r,
                                                                 const TruthWindow& window) const {
    const Texture& h = scene_.height;
    return std::visit(
        Overloaded{[&](const PlaneBase& p) {
                       return height_ ? tessellatePlane(height_, p, r, window)
                                      : tessellatePlane(h, p, r, window);
                   },
                   [&](const MeshBase& m) {
                       // The limit surface (the asset as meant) or the drawn triangles.
                       return m.truthSurface == MeshTruth::Limit
                                  ? tessellateLimitSurface(h, *m.cage, m.scheme, m.worldPerUv, r)
                                  : tessellateDrawnMesh(h, m.drawn->mesh, m.worldPerUv, r);
                   }},
        scene_.base);
}

void TruthBuilder::limitToView(const Camera& camera, const std::optional<Vec3d>& light,
                               const Displacement& disp, PixelRect block, const TexelRange* range) {
    PGT_CHECK(!base_ && !fine_);
    const PlaneBase* plane = scene_.plane();
    if (!plane) return;  // windows are cells of a plane's lattice
    const TexelRange r = range ? *range : texelRange(scene_.height);
    window_ = frameWindow(*plane, scene_.height, disp, camera, light, block, 1, &r);
    windowFine_ = frameWindow(*plane, scene_.height, disp, camera, light, block, 2, &r);
}

TruthPair TruthBuilder::build(const Displacement& disp, bool withUncertainty) {
    const int rate = scene_.truth.rate;
    // Grids are for a plane's lattice; any other base's truth is an explicit triangle list.
    const PlaneBase* plane = scene_.plane();
    const TruthGeometry geometry = plane ? scene_.truth.geometry : TruthGeometry::Triangles;
    // A window of an infinite plane is traced as it is: it covers every hit of the view.
    const bool periodic = plane && plane->infinite && !window_.limited;
    if (!base_) base_ = tessellate(rate, window_);
    TruthPair p;
    p.truth = std::make_unique<TruthSurface>(base_, disp, geometry, periodic);
    if (withUncertainty) {
        if (!fine_) fine_ = tessellate(2 * rate, windowFine_);
        p.fine = std::make_unique<TruthSurface>(fine_, disp, geometry,
                                                plane && plane->infinite && !windowFine_.limited);
    }
    return p;
}

const TruthPair& TruthBuilder::update(const Displacement& disp, bool withUncertainty) {
    if (!current_.truth || (withUncertainty && !current_.fine)) {
        current_ = build(disp, withUncertainty);
        return current_;
    }
    current_.truth->setDisplacement(disp);
    if (withUncertainty)
        current_.fine->setDisplacement(disp);
    else
        current_.fine.reset();
    return current_;
}

// Plane vertices of a truth over a window and of its 2x-rate twin over its own.
double truthVertices(const Scene& scene, const TruthWindow& window, const TruthWindow& fine) {
    const PlaneBase* plane = scene.plane();
    if (!plane) return 0;  // counted by the mesh's own estimate (scene/scene.cpp)
    auto count = [&](int r, const TruthWindow& w) {
        PlaneLattice lattice(*plane, scene.height, r);
        return w.limited ? lattice.vertices(w.uvMin, w.uvMax) : lattice.vertices();
    };
    return count(scene.truth.rate, window) +
           (scene.truth.uncertainty ? count(2 * scene.truth.rate, fine) : 0.0);
}

double truthVertices(const Scene& scene, const Camera& camera, const std::optional<Vec3d>& light,
                     PixelRect block, const TexelRange* range) {
    const PlaneBase* plane = scene.plane();
    if (!plane) return 0;
    const TexelRange r = range ? *range : texelRange(scene.height);
    const Displacement& d = scene.displacement;
    return truthVertices(scene, frameWindow(*plane, scene.height, d, camera, light, block, 1, &r),
                         frameWindow(*plane, scene.height, d, camera, light, block, 2, &r));
}

// The view's truth traced in n x n pixel blocks, each over a tessellation of only what the
// block sees, so peak memory is one block's (large maps in a whole-map view).
// Returns false (frames untouched) when no n <= 16 brings every block under the budget.
bool traceTruthInBlocks(const Scene& scene, const Camera& camera, const std::optional<Vec3d>& light,
                        double budgetVertices, TruthFrames& f) {
    if (!scene.plane()) return false;  // blocks are windows of a plane's lattice
    const int W = camera.width(), H = camera.height();
    // The map's height range once for every candidate block's windows (each would otherwise
    // scan the whole map: 7.6 s of a 4096^2 map's 64-block frame, measured).
    const TexelRange range = texelRange(scene.height);
    for (int n = 2; n <= 16; ++n) {
        std::vector<PixelRect> blocks;
        bool fits = true;
        for (int by = 0; by < n && fits; ++by)
            for (int bx = 0; bx < n && fits; ++bx) {
                PixelRect b{W * bx / n, H * by / n, W * (bx + 1) / n, H * (by + 1) / n};
                TruthWindow w = viewWindow(*scene.plane(), scene.height, scene.displacement, camera,
                                           light, b, 1, &range);
                fits = w.limited && (w.empty || truthVertices(scene, camera, light, b, &range) <=
                                                    budgetVertices);
                if (w.empty) continue;  // sees no part of the plane: every pixel misses
                blocks.push_back(b);
            }
        if (!fits) continue;
        f.truth = Image2D<TruthSample>(W, H);
        if (scene.truth.uncertainty) f.fine = Image2D<TruthSample>(W, H), f.haveFine = true;
        // The scene's map, shared unowned by every block's tessellations (they end here,
        // before the scene does): no gigabyte copy per block of a huge map.
        const std::shared_ptr<const Texture> height(std::shared_ptr<const Texture>(),
                                                    &scene.height);
        for (const PixelRect& b : blocks) {
            TruthBuilder builder(scene, height);
            builder.limitToView(camera, light, scene.displacement, b, &range);
            TruthPair pair = builder.build(scene.displacement, scene.truth.uncertainty);
            auto t0 = Clock::now();
            pair.truth->traceBlock(camera, f.truth, b, TraceMode::Coherent, light);
            f.traceMs += msSince(t0);
            if (pair.truth->stats().vertices > f.build.vertices) f.build = pair.truth->stats();
            if (pair.fine) {
                auto t1 = Clock::now();
                pair.fine->traceBlock(camera, f.fine, b, TraceMode::Coherent, light);
                f.fineMs += msSince(t1);
                if (pair.fine->stats().vertices > f.buildFine.vertices)
                    f.buildFine = pair.fine->stats();
            }
        }
        f.blocks = n * n;
        return true;
    }
    return false;
}

}  // namespace pgt
