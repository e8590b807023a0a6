// The fast paths against the plain ones: coherent tile tracing vs one ray at a time,
// in-place (s, b) updates (refit and rebuild) vs a fresh build, and the implicit plane grid
// vs the closed form of the plane.
#include <gtest/gtest.h>

#include "compare/statistics.h"
#include "scene/scene.h"
#include "test_util.h"
#include "truth/builder.h"
#include "truth/truth.h"

namespace pgt {
namespace {

Texture wavyMap(int n) {
    return test::makeTexture(
        n, n, [&](int i, int j) { return 0.5 + 0.4 * std::sin(0.37 * i) * std::cos(0.23 * j); });
}

Camera viewOf(double theta, double phi, int pixels, bool infinite) {
    Scene s;
    s.camera.theta = theta;
    s.camera.phi = phi;
    s.camera.frame = Framing::Fill;
    s.camera.fillSize = infinite ? 1.0 : 0.6;
    s.camera.width = s.camera.height = pixels;
    s.camera.jitter = true;
    return makeCamera(s);
}

// Counts pixels whose hit flag differs and the largest UV difference (texels) elsewhere.
struct FrameDiff {
    int64_t hitMismatch = 0;
    double maxTexels = 0;
};
FrameDiff diff(const Image2D<TruthSample>& a, const Image2D<TruthSample>& b, int texels) {
    FrameDiff d;
    for (size_t k = 0; k < a.size(); ++k) {
        if (a.data[k].hit != b.data[k].hit) {
            ++d.hitMismatch;
            continue;
        }
        if (a.data[k].hit)
            d.maxTexels = std::max(d.maxTexels, uvErrorTexels(a.data[k].uv, b.data[k].uv, texels,
                                                              texels, Address::Clamp));
    }
    return d;
}

// The same walk fed to Embree as tile streams or ray by ray: the same hits. Embree's
// stream kernels may round differently from rtcIntersect1: 1e-3 texel and no hit flips.
TEST(TruthPerf, CoherentTilesMatchSingleRays) {
    Texture t = wavyMap(64);
    for (bool infinite : {false, true}) {
        PlaneBase plane;
        plane.infinite = infinite;
        auto base = tessellatePlane(t, plane, 2);
        TruthSurface surface(base, Displacement{0.08, -0.04}, TruthGeometry::Grid, infinite);
        for (double theta : {0.0, 45.0, 80.0, 88.0}) {
            Camera cam = viewOf(theta, 25, 75, infinite);  // 75: partial edge tiles
            auto single = surface.traceFrame(cam, TraceMode::Single);
            auto coherent = surface.traceFrame(cam, TraceMode::Coherent);
            FrameDiff d = diff(single, coherent, 64);
            EXPECT_EQ(d.hitMismatch, 0) << "theta " << theta << " infinite " << infinite;
            EXPECT_LT(d.maxTexels, 1e-3) << "theta " << theta << " infinite " << infinite;
        }
    }
}

// A surface moved to a new (s, b) in place traces like one built there: rebuilding is
// deterministic (bit-identical UVs), a refitted BVH finds the same hits (1e-6 texel).
TEST(TruthPerf, UpdateMatchesFreshBuild) {
    Texture t = wavyMap(48);
    auto base = tessellatePlane(t, PlaneBase{}, 2);
    Camera cam = viewOf(70, 40, 64, false);
    for (TruthGeometry g : {TruthGeometry::Grid, TruthGeometry::Triangles}) {
        for (TruthUpdate u : {TruthUpdate::Rebuild, TruthUpdate::Refit}) {
            TruthSurface moved(base, Displacement{0.02, 0.0}, g, false);
            moved.setDisplacement(Displacement{0.1, -0.07}, u);
            EXPECT_EQ(moved.lastUpdate(), u);
            TruthSurface fresh(base, Displacement{0.1, -0.07}, g, false);
            FrameDiff d = diff(moved.traceFrame(cam), fresh.traceFrame(cam), 48);
            EXPECT_EQ(d.hitMismatch, 0);
            EXPECT_LT(d.maxTexels, u == TruthUpdate::Rebuild ? 1e-12 : 1e-6);
        }
    }
    // A bias change on a plane moves the rays instead of the sheet, and a plane is always
    // built that way, so the result does not depend on the path to (s, b): bit-identical.
    for (TruthGeometry g : {TruthGeometry::Grid, TruthGeometry::Triangles}) {
        TruthSurface moved(base, Displacement{0.1, 0.02}, g, false);
        moved.setDisplacement(Displacement{0.1, -0.07});
        EXPECT_EQ(moved.lastUpdate(), TruthUpdate::Translate);
        TruthSurface fresh(base, Displacement{0.1, -0.07}, g, false);
        FrameDiff d = diff(moved.traceFrame(cam), fresh.traceFrame(cam), 48);
        EXPECT_EQ(d.hitMismatch, 0);
        EXPECT_EQ(d.maxTexels, 0.0);
    }
    TruthSurface autoGrid(base, Displacement{0.02, 0.0}, TruthGeometry::Grid, false);
    autoGrid.setDisplacement(Displacement{0.05, 0.0});
    EXPECT_EQ(autoGrid.lastUpdate(), TruthUpdate::Rebuild);  // measured faster for grids
    TruthSurface autoTri(base, Displacement{0.02, 0.0}, TruthGeometry::Triangles, false);
    autoTri.setDisplacement(Displacement{0.05, 0.0});
    EXPECT_EQ(autoTri.lastUpdate(), TruthUpdate::Refit);  // measured faster for triangles
}

// The implicit grid is the plane of docs/model.md §2: vertex (i, j) at centre + ((i/nu - 1/2) L,
// (j/nv - 1/2) L, 0) with UV (i/nu, j/nv) x tiling, normal +z, height sampled there.
TEST(TruthPerf, ImplicitGridIsThePlane) {
    Texture t = wavyMap(16);
    PlaneBase plane;
    plane.size = 3.0;
    plane.tiling = 2.0;
    plane.center = Vec3d(5, -2, 1);
    auto base = tessellatePlane(t, plane, 3);
    ASSERT_EQ(base->grid->nu, 96);
    ASSERT_EQ(base->vertexCount(), size_t(97 * 97));
    EXPECT_EQ(base->bytes(), t.texels.size() * sizeof(float));  // nothing per vertex
    for (int j : {0, 1, 50, 96})
        for (int i : {0, 7, 95, 96}) {
            size_t k = base->grid->gridIndex(i, j);
            Vec3d p = base->positionAt(k) + base->origin;
            EXPECT_NEAR(p.x, 5 + (i / 96.0 - 0.5) * 3, 1e-12);
            EXPECT_NEAR(p.y, -2 + (j / 96.0 - 0.5) * 3, 1e-12);
            EXPECT_NEAR(p.z, 1, 1e-12);
            EXPECT_NEAR(base->uvAt(k).x, 2 * i / 96.0, 1e-12);
            EXPECT_NEAR(base->uvAt(k).y, 2 * j / 96.0, 1e-12);
            EXPECT_EQ(base->normalAt(k), Vec3d(0, 0, 1));
            EXPECT_EQ(base->heightAt(k), sampleBilinear<double>(t, base->uvAt(k)));
        }
    // The last vertex is exactly the tile's edge (the periodic walk relies on it).
    EXPECT_EQ(base->uvAt(base->grid->gridIndex(96, 96)), Vec2d(2, 2));
}

// A window of an infinite plane (the part a close view sees) is the same lattice as the
// whole tile: the view's truth is the same, hit for hit, without the periodic walk.
TEST(TruthPerf, ViewWindowTracesLikeTheWholePlane) {
    Texture t = wavyMap(64);
    PlaneBase plane;
    plane.infinite = true;
    Displacement disp{0.08, -0.04};
    Scene s;
    s.camera.theta = 65;
    s.camera.phi = 35;
    s.camera.frame = Framing::Fill;
    s.camera.fillSize = 0.2;
    s.camera.width = s.camera.height = 64;
    s.camera.target = Vec3d(0.45, 0.3, 0);  // across the tile's corner: the window unwraps
    Camera cam = makeCamera(s);
    TruthWindow w = viewWindow(plane, t, disp, cam, std::nullopt);
    ASSERT_TRUE(w.limited);
    EXPECT_LT((w.uvMax.x - w.uvMin.x) * (w.uvMax.y - w.uvMin.y), 0.25);
    auto windowed = tessellatePlane(t, plane, 2, w);
    auto whole = tessellatePlane(t, plane, 2);
    EXPECT_LT(windowed->vertexCount() * 4, whole->vertexCount());
    TruthSurface a(windowed, disp, TruthGeometry::Grid, false);
    TruthSurface b(whole, disp, TruthGeometry::Grid, true);
    FrameDiff d = diff(a.traceFrame(cam), b.traceFrame(cam), 64);
    EXPECT_EQ(d.hitMismatch, 0);
    EXPECT_LT(d.maxTexels, 1e-4);  // the float rays start at different points
}

// One lattice size formula: the memory estimate and the block planner (truthVertices) count
// exactly the vertices the tessellation builds, whole or windowed, at the rate and 2x.
TEST(TruthPerf, VertexCountsAgreeWithTheTessellation) {
    Scene s;
    s.height = wavyMap(48);
    s.plane()->tiling = 1.3;  // not whole texels per tile: ceil matters
    s.plane()->infinite = true;
    s.truth.rate = 3;
    s.truth.uncertainty = true;
    auto count = [&](const TruthWindow& w) {
        return double(tessellatePlane(s.height, *s.plane(), 3, w)->vertexCount() +
                      tessellatePlane(s.height, *s.plane(), 6, w)->vertexCount());
    };
    EXPECT_EQ(truthVertices(s, TruthWindow{}, TruthWindow{}), count(TruthWindow{}));
    TruthWindow w;
    w.limited = true;
    w.uvMin = Vec2d(-0.213, 0.4017);  // an infinite plane's window may leave the tile
    w.uvMax = Vec2d(0.377, 1.52);
    EXPECT_EQ(truthVertices(s, w, w), count(w));
    s.truth.uncertainty = false;
    EXPECT_EQ(truthVertices(s, TruthWindow{}, TruthWindow{}),
              double(tessellatePlane(s.height, *s.plane(), 3)->vertexCount()));
}

}  // namespace
}  // namespace pgt
