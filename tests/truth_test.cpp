// Truth: closed forms (constant and ramp height), convergence with rate, geometry variants.
#include "truth/truth.h"

#include <gtest/gtest.h>

#include "compare/statistics.h"
#include "compare/uncertainty.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

// The ray through the base point of uv0 (unit-size plane centred at `center`) along -V.
Ray rayThrough(Vec2d uv0, Vec3d v, Vec3d center = Vec3d(0), double size = 1.0) {
    return {center + Vec3d((uv0.x - 0.5) * size, (uv0.y - 0.5) * size, 0.0), -v, true};
}

class TruthGeometries : public ::testing::TestWithParam<TruthGeometry> {};

// Constant height c: the sheet is the plane z = l*(s*c + b), so the hit's UV is
// uv0 + V.xy / V.z * (s*c + b) exactly (docs/model.md §3). 1e-4 texel: float32 positions of a
// unit-size sheet resolve ~1e-7 UV = 6e-6 texel at W = 64.
TEST_P(TruthGeometries, ExactOnConstantHeight) {
    const double c = 0.4, s = 0.08, b = -0.05;
    Texture t = test::makeTexture(64, 64, [&](int, int) { return c; });
    TruthSurface surface(t, PlaneBase{}, Displacement{s, b}, 2, GetParam());
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 300; ++k) {
        Vec3d v = viewFromAngles(80 * uni(rng), 360 * uni(rng));
        Vec2d offset = Vec2d(v.x, v.y) / v.z * (s * c + b);
        Vec2d want(0.05 + 0.9 * uni(rng), 0.05 + 0.9 * uni(rng));
        Vec2d uv0 = want - offset;  // a base point whose true hit lies on the sheet
        TruthSample got = surface.trace(rayThrough(uv0, v));
        ASSERT_TRUE(got.hit) << "uv0 " << uv0.x << "," << uv0.y;
        double e = uvErrorTexels(got.uv, want, 64, 64, Address::Repeat);
        EXPECT_LT(e, 1e-4) << "theta " << degrees(std::acos(v.z)) << " uv0 " << uv0.x << ","
                           << uv0.y;
    }
}

// Ramp h = a*u + c0 (clamp; exact between the first and last texel centres): the hit solves
// u = u0 + k_x (s (a u + c0) + b), k = V.xy / V.z, so u = (u0 + k_x (s c0 + b)) / (1 - k_x s a).
TEST_P(TruthGeometries, ExactOnRamp) {
    const int w = 64;
    const double a = 0.8, c0 = 0.1, s = 0.1, b = -0.05;
    Texture t = test::makeTexture(
        w, 16, [&](int i, int) { return c0 + a * (i + 0.5) / w; }, Address::Clamp);
    TruthSurface surface(t, PlaneBase{}, Displacement{s, b}, 2, GetParam());
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    int checked = 0;
    for (int k = 0; k < 400; ++k) {
        Vec3d v = viewFromAngles(75 * uni(rng), 360 * uni(rng));
        Vec2d uv0(uni(rng), uni(rng));
        double kx = v.x / v.z, ky = v.y / v.z;
        double u = (uv0.x + kx * (s * c0 + b)) / (1 - kx * s * a);
        double vv = uv0.y + ky * (s * (a * u + c0) + b);
        if (u < 1.0 / w || u > 1 - 1.0 / w || vv < 0.02 || vv > 0.98) continue;  // linear part
        TruthSample got = surface.trace(rayThrough(uv0, v));
        ASSERT_TRUE(got.hit);
        EXPECT_LT(uvErrorTexels(got.uv, Vec2d(u, vv), w, 16, Address::Clamp), 1e-4)
            << "uv0 " << uv0.x << "," << uv0.y << " V " << v.x << "," << v.y << "," << v.z;
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

INSTANTIATE_TEST_SUITE_P(Truth, TruthGeometries,
                         ::testing::Values(TruthGeometry::Grid, TruthGeometry::Triangles),
                         [](const auto& param) {
                             return param.param == TruthGeometry::Grid ? "Grid" : "Triangles";
                         });

Scene smoothScene(int rate, TruthGeometry g = TruthGeometry::Grid) {
    Scene s = test::planeScene(test::smoothTexture(32, 32), 0.08, -0.04, 60, 30, 128, {}, rate);
    s.truth.geometry = g;
    return s;
}

Image2D<TruthSample> truthFrame(const Scene& s) {
    TruthSurface surface(s.height, *s.plane(), s.displacement, s.truth.rate, s.truth.geometry);
    return surface.traceFrame(makeCamera(s));
}

// docs/model.md §5: the tessellation error is measured, and it must shrink as the rate doubles.
TEST(Truth, UncertaintyShrinksWhenRateDoubles) {
    std::vector<double> p99;
    for (int rate : {1, 2, 4}) {
        Scene a = smoothScene(rate), b = smoothScene(2 * rate);
        TruthUncertainty u =
            compareTruthFrames(truthFrame(a), truthFrame(b), a.height, a.height.address);
        p99.push_back(u.p99Texels);
        EXPECT_GT(u.pixelsCompared, 3000);
    }
    EXPECT_LT(p99[1], p99[0] * 0.6) << p99[0] << " -> " << p99[1];
    EXPECT_LT(p99[2], p99[1] * 0.6) << p99[1] << " -> " << p99[2];
}

TEST(Truth, GridAndTrianglesAgree) {
    auto a = truthFrame(smoothScene(4, TruthGeometry::Grid));
    auto b = truthFrame(smoothScene(4, TruthGeometry::Triangles));
    double worst = 0;
    int64_t mismatch = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        if (a.data[k].hit != b.data[k].hit) ++mismatch;
        if (a.data[k].hit && b.data[k].hit)
            worst =
                std::max(worst, uvErrorTexels(a.data[k].uv, b.data[k].uv, 32, 32, Address::Repeat));
    }
    // Same vertices and the same cell diagonal: only float rounding inside Embree differs.
    EXPECT_LT(worst, 1e-3);
    EXPECT_LE(mismatch, 4);  // a ray exactly on the sheet's border may go either way
}

// The sheet is built relative to its centre: a plane 1e5 units from the origin keeps the
// precision of one at the origin.
TEST(Truth, PlaneFarFromTheOrigin) {
    const double c = 0.4, s = 0.08, b = -0.05;
    Texture t = test::makeTexture(64, 64, [&](int, int) { return c; });
    PlaneBase plane;
    plane.center = Vec3d(1e5, -2e5, 3e4);
    TruthSurface surface(t, plane, Displacement{s, b}, 2, TruthGeometry::Grid);
    Vec3d v = viewFromAngles(50, 40);
    Vec2d want(0.4, 0.6);
    Vec2d uv0 = want - Vec2d(v.x, v.y) / v.z * (s * c + b);
    TruthSample got = surface.trace(rayThrough(uv0, v, plane.center));
    ASSERT_TRUE(got.hit);
    EXPECT_LT(uvErrorTexels(got.uv, want, 64, 64, Address::Repeat), 1e-4);
}

// An infinite plane (the tile repeated): at grazing angles the ray meets the sheet tiles
// away from its base point, and the truth UV is unwrapped by the tiles it crossed.
TEST(Truth, PeriodicPlaneHitsBeyondTheTile) {
    const double c = 0.9, s = 0.1, b = 0.0;
    Texture t = test::makeTexture(32, 32, [&](int, int) { return c; });
    PlaneBase plane;
    plane.tiling = 2;  // the tile holds two texture repeats
    plane.size = 1.5;
    auto base = tessellatePlane(t, plane, 2);
    TruthSurface surface(base, Displacement{s, b}, TruthGeometry::Grid, true);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        Vec3d v = viewFromAngles(70 + 19.5 * uni(rng), 360 * uni(rng));
        Vec2d uv0(2 * uni(rng), 2 * uni(rng));
        Vec2d want = uv0 + Vec2d(v.x, v.y) / v.z * (s * c + b);  // may be many tiles away
        Vec3d p(uv0.x * 0.75 - 0.75, uv0.y * 0.75 - 0.75, 0.0);  // l = 0.75
        TruthSample got = surface.trace({p, -v, true});
        ASSERT_TRUE(got.hit) << "theta " << degrees(std::acos(v.z));
        // Unwrapped: compare without the repeat wrap. Far hits lose float precision in the
        // long ray (|t| up to ~0.09 * tan(89.5) / 0.75 ~ 14 UV): 2e-3 texel.
        EXPECT_LT(uvErrorTexels(got.uv, want, 32, 32, Address::Clamp), 2e-3)
            << "theta " << degrees(std::acos(v.z)) << " want " << want.x << "," << want.y;
    }
}

}  // namespace
}  // namespace pgt
