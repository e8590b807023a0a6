// Rasteriser: top-left rule on shared edges, perspective-correct UV, tangent-space V.
#include "raster/raster.h"

#include <gtest/gtest.h>

#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

BaseMesh singleTriangle(const BaseMesh& m, int tri) {
    BaseMesh out = m;
    out.indices = {m.indices[3 * tri], m.indices[3 * tri + 1], m.indices[3 * tri + 2]};
    return out;
}

// Pixels on the shared diagonal belong to exactly one of the two triangles (top-left rule):
// no pixel twice, none lost.
TEST(Raster, SharedEdgeIsCoveredExactlyOnce) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 20; ++k) {
        // Small resolutions make pixel centres land on the diagonal often.
        int res = 8 + k;
        Camera cam =
            k % 2 ? Camera::orthographic(-viewFromAngles(uni(rng) * 60, uni(rng) * 360), Vec3d(0),
                                         Vec3d(0, 0, 1) + Vec3d(0.1, 0.2, 0), 1.5, res, res)
                  : Camera::orthographic(Vec3d(0, 0, -1), Vec3d(0), Vec3d(0, 1, 0), 1.0, res, res);
        auto a = rasterize(singleTriangle(plane, 0), cam, {true});
        auto b = rasterize(singleTriangle(plane, 1), cam, {true});
        auto both = rasterize(plane, cam, {true});
        for (size_t p = 0; p < a.size(); ++p) {
            EXPECT_FALSE(a.data[p].covered && b.data[p].covered) << "pixel " << p << " case " << k;
            EXPECT_EQ(a.data[p].covered || b.data[p].covered, both.data[p].covered);
        }
    }
}

// Head-on, the plane fills pixel centres exactly: an 8x8 image of the unit plane covers all
// 64 pixels and uv0 is the pixel centre's UV.
TEST(Raster, HeadOnPixelCentresMapToUv) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera cam = Camera::orthographic(Vec3d(0, 0, -1), Vec3d(0), Vec3d(0, 1, 0), 1.0, 8, 8);
    RasterStats st;
    auto f = rasterize(plane, cam, {true}, &st);
    EXPECT_EQ(st.covered, 64);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_NEAR(f.at(x, y).uv0.x, (x + 0.5) / 8, 1e-12);
            EXPECT_NEAR(f.at(x, y).uv0.y, 1 - (y + 0.5) / 8, 1e-12);  // image y down, v up
        }
}

// Perspective-correct interpolation: uv0 equals the UV where the pixel's ray meets z = 0.
TEST(Raster, PerspectiveCorrectUvMatchesRayPlaneIntersection) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 2.0, 3.0);  // l = 2/3 world units per UV
    Camera cam =
        Camera::pinhole(Vec3d(0.3, -2.5, 1.2), Vec3d(0, 0.2, 0), Vec3d(0, 0, 1), 50, 96, 64);
    auto f = rasterize(plane, cam, {true});
    int covered = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            if (!f.at(x, y).covered) continue;
            ++covered;
            Ray r = cam.pixelRay(x, y);
            double t = -r.origin.z / r.dir.z;
            Vec3d p = r.origin + r.dir * t;
            Vec2d uv((p.x + 1) * 1.5, (p.y + 1) * 1.5);
            ASSERT_NEAR(f.at(x, y).uv0.x, uv.x, 1e-9) << x << "," << y;
            ASSERT_NEAR(f.at(x, y).uv0.y, uv.y, 1e-9) << x << "," << y;
            Vec3d v = glm::normalize(cam.eye() - p);
            ASSERT_NEAR(f.at(x, y).viewTangent.z, v.z, 1e-9);
        }
    EXPECT_GT(covered, 1000);
}

// An orthographic view from (theta, phi) gives V = MODEL.md §4's direction at every pixel.
TEST(Raster, OrthographicViewVectorIsTheViewAngle) {
    Scene s = test::planeScene(test::smoothTexture(8, 8), 0.05, -0.025, 63, 217, 64, {});
    Camera cam = makeCamera(s);
    auto f = rasterize(makePlaneMesh(Vec3d(0), 1, 1), cam, {true});
    Vec3d want = viewFromAngles(63, 217);
    int covered = 0;
    for (const auto& fr : f.data) {
        if (!fr.covered) continue;
        ++covered;
        EXPECT_NEAR(fr.viewTangent.x, want.x, 1e-12);
        EXPECT_NEAR(fr.viewTangent.y, want.y, 1e-12);
        EXPECT_NEAR(fr.viewTangent.z, want.z, 1e-12);
    }
    EXPECT_GT(covered, 500);
}

TEST(Raster, BackFacesAreCulledOnRequest) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera below = Camera::pinhole(Vec3d(0, 0, -2), Vec3d(0), Vec3d(0, 1, 0), 60, 32, 32);
    RasterStats culled, drawn;
    rasterize(plane, below, {true}, &culled);
    rasterize(plane, below, {false}, &drawn);
    EXPECT_EQ(culled.covered, 0);
    EXPECT_EQ(culled.trianglesCulled, 2);
    EXPECT_GT(drawn.covered, 100);
}

// A pinhole eye just above the plane: triangles crossing the near plane are clipped, not lost.
TEST(Raster, NearPlaneClippingKeepsTheVisiblePart) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera cam =
        Camera::pinhole(Vec3d(0, -0.45, 0.01), Vec3d(0, 0.5, 0), Vec3d(0, 0, 1), 90, 64, 64);
    RasterStats st;
    auto f = rasterize(plane, cam, {true}, &st);
    EXPECT_GT(st.covered, 200);
    for (const auto& fr : f.data)
        if (fr.covered) {
            EXPECT_TRUE(allFinite(fr.uv0) && allFinite(fr.viewTangent));
        }
}

}  // namespace
}  // namespace pgt
