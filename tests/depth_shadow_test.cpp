// Depth offsets and self-shadowing (docs/model.md §5b, §6c, §7b) against closed forms: a
// constant height, head-on views, the plane's exact depth of any hit, a step edge's shadow
// length, a flat map's lack of shadows, and the truth's shadow rays against a brute-force
// march of the bilinear surface.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "evaluate/evaluate.h"
#include "frame/render.h"
#include "methods/builtin/shadow.h"
#include "test_util.h"
#include "truth/truth.h"

namespace pgt {
namespace {

// One C++ method on one fragment, as the pipeline runs it: its uv' and its depth offset.
struct Answer {
    Vec2f uv;
    float depth;
};
Answer runAt(const MethodConfig& cfg, MethodTextureCache& cache, const Displacement& d, Vec2f uv0,
             Vec3f v) {
    MethodContext<float> c = makeMethodContext<float>(cache.get(cfg, d));
    Answer a;
    a.uv = runMethod<float>(*cfg.builtin(), c, uv0, v);
    a.depth = -c.foundHeight / v.z;
    return a;
}

// Methods exact on a constant height (their answer lies on the plane z = s h + b up to float
// rounding), and those exact up to their search's resolution.
const char* const kExactOnConstant[] = {"parallax", "offset_limited", "pom",       "secant",
                                        "contact",  "maxmip",         "iterative", "tangent_plane"};
const char* const kSearchOnConstant[] = {"steep", "relief", "cone", "relaxed_cone"};

TEST(DepthOffset, ConstantHeightIsExactForEveryExactMethod) {
    const Texture map = test::makeTexture(16, 16, [](int, int) { return 0.3; });
    const Displacement d{0.08, -0.06};
    const double z = 0.08 * 0.3 - 0.06;  // the surface's height, UV units
    MethodTextureCache cache(map, UvExtent(1.0));
    for (double theta : {0.0, 30.0, 60.0, 80.0})
        for (double phi : {0.0, 70.0, 200.0}) {
            const Vec3f v(viewFromAngles(theta, phi));
            const double want = -z / double(v.z);
            for (const char* name : kExactOnConstant) {
                const Answer a = runAt(test::method(std::string("\"") + name + "\""), cache, d,
                                       Vec2f(0.37f, 0.61f), v);
                EXPECT_NEAR(a.depth, want, 2e-6 * (1 + std::fabs(want)) / double(v.z))
                    << name << " theta " << theta;
            }
            for (const char* name : kSearchOnConstant) {
                const MethodConfig cfg = test::method(std::string("\"") + name + "\"");
                const Answer a = runAt(cfg, cache, d, Vec2f(0.37f, 0.61f), v);
                // Their step in height: steep a layer (at most 1/8 of s), the others finer.
                EXPECT_NEAR(a.depth, want, 0.08 / 8 / double(v.z)) << name << " theta " << theta;
            }
            // The polygon itself: no offset.
            EXPECT_EQ(runAt(test::method("\"none\""), cache, d, Vec2f(0.3f, 0.2f), v).depth, 0.0f);
        }
}

// Head-on, the exact methods land on uv0 at the surface: the depth is minus the height there.
TEST(DepthOffset, HeadOnDepthIsTheHeight) {
    const Texture map = test::smoothTexture(32, 32);
    const Displacement d{0.1, -0.05};
    MethodTextureCache cache(map, UvExtent(1.0));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (int k = 0; k < 200; ++k) {
        const Vec2f uv0(uni(rng), uni(rng));
        const double want = -(0.1 * sampleBilinear<double>(map, Vec2d(uv0)) - 0.05);
        for (const char* name : {"parallax", "pom", "secant", "contact", "maxmip"}) {
            const Answer a =
                runAt(test::method(std::string("\"") + name + "\""), cache, d, uv0, Vec3f(0, 0, 1));
            EXPECT_NEAR(a.depth, want, 1e-6) << name << " at " << uv0.x << ", " << uv0.y;
        }
    }
}

// A ramp h = a + k u (exact under bilinear between the first and last texel centres): the eye
// ray uv(z) = uv0 + V.xy / V.z z meets z = s (a + k u) + b at z = (s (a + k u0) + b) /
// (1 - s k V.x / V.z); the exact methods' depth is -z / V.z.
TEST(DepthOffset, RampIsExactForTheExactMethods) {
    const double a = 0.2, k = 0.6;
    const Texture map = test::makeTexture(
        32, 32, [&](int i, int) { return a + k * (i + 0.5) / 32; }, Address::Clamp);
    const Displacement d{0.1, -0.07};
    MethodTextureCache cache(map, UvExtent(1.0));
    for (double theta : {20.0, 50.0, 75.0})
        for (double phi : {0.0, 150.0, 250.0}) {
            const Vec3f v(viewFromAngles(theta, phi));
            const Vec2f uv0(0.45f, 0.5f);
            const double vx = v.x, vz = v.z;
            const double z = (0.1 * (a + k * double(uv0.x)) - 0.07) / (1 - 0.1 * k * vx / vz);
            for (const char* name : {"pom", "secant", "contact", "maxmip"}) {
                const Answer ans =
                    runAt(test::method(std::string("\"") + name + "\""), cache, d, uv0, v);
                EXPECT_NEAR(ans.depth, -z / vz, 1e-5 / vz)
                    << name << " theta " << theta << " phi " << phi;
            }
        }
}

Scene litPlane(Texture map, double s, double b, double theta, double phi, int resolution,
               const char* methods) {
    Scene sc = test::planeScene(std::move(map), s, b, theta, phi, resolution,
                                parseMethods(nlohmann::json::parse(methods), "test", "methods"));
    sc.truth.uncertainty = false;
    sc.light = LightSpec{45, 180};
    return sc;
}

// On a plane (orthographic), the eye ray meets height z at -z / V.z beyond the drawn point:
// the truth's depth of every hit is -(s h(uv_true) + b) / cos(theta), exactly on a ramp
// (its tessellation is exact) and to the tessellation's error on a smooth map.
TEST(DepthOffset, TruthDepthOnAPlaneIsTheHitsHeightOverCosTheta) {
    struct Case {
        Texture map;
        double tolerance;
    };
    const Texture ramp = test::makeTexture(
        16, 16, [](int i, int) { return 0.2 + 0.6 * (i + 0.5) / 16; }, Address::Clamp);
    for (const Case& c : {Case{ramp, 1e-5}, Case{test::smoothTexture(32, 32), 2e-4}})
        for (double theta : {0.0, 40.0, 70.0}) {
            Scene sc = litPlane(c.map, 0.1, -0.07, theta, 30, 96, R"(["pom"])");
            sc.height.address = c.map.address;
            const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
            int checked = 0;
            for (const TruthSample& t : r.truth.data) {
                if (!std::isfinite(t.depth)) continue;
                const double z = 0.1 * sampleBilinear<double>(sc.height, t.uv) - 0.07;
                EXPECT_NEAR(t.depth, -z / std::cos(radians(theta)), c.tolerance)
                    << "theta " << theta;
                ++checked;
            }
            EXPECT_GT(checked, 1000) << "theta " << theta;
            EXPECT_EQ(r.methods[0].stats.depthError.count, r.methods[0].stats.error.count);
        }
}

// maxmip traces the bilinear surface exactly, the truth its tessellation: their depths agree
// to the tessellation's error, far closer than steep's layers.
TEST(DepthOffset, MaxMipAgreesWithTheTruth) {
    Scene sc = litPlane(test::smoothTexture(32, 32), 0.08, -0.04, 55, 20, 128,
                        R"(["maxmip", {"name": "steep", "min_layers": 8, "max_layers": 8}])");
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    const FrameStats& maxmip = r.methods[0].stats;
    const FrameStats& steep = r.methods[1].stats;
    EXPECT_GT(maxmip.depthError.count, 5000);
    EXPECT_LT(maxmip.depthError.p90, 2e-3);
    EXPECT_LT(maxmip.depthError.p90 * 10, steep.depthError.p90);
}

// A flat map casts no shadow: the truth and every march light every pixel.
TEST(Shadows, AFlatMapCastsNone) {
    Scene sc = litPlane(test::makeTexture(16, 16, [](int, int) { return 0.5; }), 0.1, -0.05, 50, 0,
                        64, R"(["pom", "parallax", {"preset": "tatarchuk_soft"}])");
    sc.light = LightSpec{70, 120};
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    for (const MethodFrame& m : r.methods) {
        EXPECT_GT(m.stats.shadow.compared, 2000) << m.config.label;
        EXPECT_EQ(m.stats.shadow.truthDark, 0) << m.config.label;
        EXPECT_EQ(m.stats.shadow.methodDark, 0) << m.config.label;
    }
}

// A plateau of height s stepping down along +u, the light from -u at 45 degrees: its shadow
// (the falling edge facing away, then the floor) reaches s tan 45 = s beyond the edge's top,
// from u = 31.5 / 64 to 31.5 / 64 + s. Head-on, each row counts that many pixels.
TEST(Shadows, AStepEdgeCastsAShadowOfItsHeight) {
    const Texture map =
        test::makeTexture(64, 64, [](int i, int) { return i >= 16 && i < 32 ? 1.0 : 0.0; });
    Scene sc = litPlane(map, 0.1, 0.0, 0, 90, 240,  // phi 90: u runs along the image's rows
                        R"([{"name": "pom", "shadow_steps": 128, "label": "pom"},
                            {"name": "pom", "shadow": "soft", "label": "soft"}])");
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    const Image2D<Fragment>& f = r.fragments;
    const int y = 120;
    const double du = std::fabs(f.at(121, y).uv0.x - f.at(120, y).uv0.x);
    ASSERT_GT(du, 0);
    const double want = 0.1 / du;
    int truthDark = 0, marchDark = 0, softDark = 0;
    for (int x = 0; x < 240; ++x) {
        const TruthSample& t = r.truth.at(x, y);
        const MethodPixel& m = r.methods[0].pixels.at(x, y);
        if (!t.hit || !m.covered) continue;
        truthDark += t.shadow == kShadowDark;
        marchDark += m.shadow == kShadowDark;
        softDark += r.methods[1].pixels.at(x, y).shadow == kShadowDark;
        // Inside the shadow's span, both agree (away from its two ends).
        const double u = t.uv.x;
        if (u > 31.5 / 64 + 2 * du && u < 31.5 / 64 + 0.1 - 2 * du) {
            EXPECT_EQ(t.shadow, kShadowDark) << "u " << u;
            EXPECT_EQ(m.shadow, kShadowDark) << "u " << u;
        }
    }
    EXPECT_NEAR(truthDark, want, 2.0);
    EXPECT_NEAR(marchDark, want, 2.0);
    // Tatarchuk's seven taps reach L.xy s f, f <= 0.88, and a tap darkens more than half only
    // while (1 - f) w 0.58 > 1/2: up to f = 0.66 (w 4), 0.707 x 0.1 x 0.66 = 0.047 UV past
    // the edge (plus the bilinear ramp's texel): half the true shadow's length.
    EXPECT_GT(softDark, 0.035 / du);
    EXPECT_LT(softDark, 0.065 / du);
}

// The truth's shadow rays against a brute-force march of the bilinear surface in double:
// from the hit, 4,000 steps toward the light; in shadow where the surface faces away or any
// step lies below it. They disagree only where the light grazes an edge.
TEST(Shadows, TruthRaysAgreeWithABruteForceMarch) {
    const Texture map = test::smoothTexture(32, 32);
    const double s = 0.12, b = -0.06;
    Scene sc = litPlane(map, s, b, 30, 0, 128, R"(["none"])");
    sc.light = LightSpec{60, 30};
    sc.truth.rate = 8;
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    const Vec3d L = viewFromAngles(60, 30);
    auto height = [&](Vec2d uv) { return s * sampleBilinear<double>(map, uv) + b; };
    int compared = 0, differ = 0;
    for (const TruthSample& t : r.truth.data) {
        if (!t.hit) continue;
        const double z0 = height(t.uv), top = s + b;
        // The bilinear surface's normal from central differences of its height.
        const double e = 1e-5;
        const Vec3d n(-(height(t.uv + Vec2d(e, 0)) - height(t.uv - Vec2d(e, 0))) / (2 * e),
                      -(height(t.uv + Vec2d(0, e)) - height(t.uv - Vec2d(0, e))) / (2 * e), 1);
        bool dark = glm::dot(n, L) <= 0;
        const int steps = 4000;
        for (int k = 1; k <= steps && !dark; ++k) {
            const double z = z0 + (top - z0) * k / steps;
            const Vec2d uv = t.uv + Vec2d(L.x, L.y) / L.z * (z - z0);
            if (uv.x < 0 || uv.x > 1 || uv.y < 0 || uv.y > 1) break;  // past the plane's sheet
            dark = height(uv) > z;
        }
        ++compared;
        differ += dark != (t.shadow == kShadowDark);
    }
    EXPECT_GT(compared, 10000);
    EXPECT_LT(double(differ) / compared, 0.01) << differ << " of " << compared;
}

// A plateau of height 1 from u = 44/64 on, outside a small head-on view over the floor
// (u 0.35 to 0.55), the light from +u at 85 degrees: the plateau's shadow reaches
// s tan 85 = 1.14 UV beyond its edge, so every pixel of the view is dark (closed form: the
// ray from any floor point of the view climbs at most 0.33 / tan 85 = 0.029 < s before it
// meets the plateau's wall). The shadow rays must see relief the view does not: the truth's
// window reaches toward the light, in both passes.
TEST(Shadows, AStepBeyondTheViewDarkensTheWholeView) {
    const Texture map = test::makeTexture(
        64, 64, [](int i, int) { return i >= 44 ? 1.0 : 0.0; }, Address::Clamp);
    Scene sc = litPlane(map, 0.1, 0.0, 0, 0, 64, R"(["pom"])");
    sc.height.address = Address::Clamp;
    sc.light = LightSpec{85, 0};
    sc.truth.uncertainty = true;
    sc.camera.frame = Framing::View;
    sc.camera.viewHeight = 0.2;
    sc.camera.target = Vec3d(0.45 - 0.5, 0, 0);  // uv (0.45, 0.5) of the unit plane
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    int dark = 0, marchDark = 0;
    for (size_t k = 0; k < r.truth.size(); ++k) {
        ASSERT_TRUE(r.truth.data[k].hit);
        ASSERT_LT(r.truth.data[k].uv.x, 0.56);  // the view sees only the floor
        dark += r.truth.data[k].shadow == kShadowDark;
        marchDark += r.methods[0].pixels.data[k].shadow == kShadowDark;
    }
    EXPECT_EQ(dark, 64 * 64);
    EXPECT_EQ(marchDark, 64 * 64);
    ASSERT_TRUE(r.haveUncertainty);
    EXPECT_EQ(r.uncertainty.shadowMismatch, 0);  // the finer pass agrees
}

// Half a finite plane of bricks framed at 80 degrees, the light at 75: its truth over the
// view's window (reaching toward the light) casts exactly the shadows of a truth built over
// the whole plane. Before the window reached toward the light, mortar joints whose shadow
// falls from bricks outside the view were lit.
TEST(Shadows, AWindowedTruthCastsTheShadowsOfTheWholePlane) {
    const Texture map = test::bricks(32);
    Scene sc = litPlane(map, 0.1, -0.05, 60, 20, 96, R"(["none"])");
    sc.light = LightSpec{82, 200};
    sc.camera.frame = Framing::Fill;
    sc.camera.fillSize = 0.3;
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    const Camera cam = makeCamera(sc);
    TruthSurface whole(map, *sc.plane(), sc.displacement, sc.truth.rate, TruthGeometry::Grid);
    const Image2D<TruthSample> all =
        whole.traceFrame(cam, TraceMode::Coherent, lightToward(sc.view()));
    int compared = 0, differ = 0, dark = 0;
    for (size_t k = 0; k < all.size(); ++k) {
        if (!all.data[k].hit || !r.truth.data[k].hit) continue;
        ++compared;
        dark += all.data[k].shadow == kShadowDark;
        differ += all.data[k].shadow != r.truth.data[k].shadow;
    }
    EXPECT_GT(compared, 9000);
    EXPECT_GT(dark, 500);  // the test sees shadows at all
    EXPECT_EQ(differ, 0) << "of " << compared << " dark " << dark;
}

// A light at exactly 90 degrees lies in the plane (its vector's z is 0, not cos(pi/2)'s
// 6e-17): every hit of a plane's relief is dark, for the truth and every march, and no
// shadow ray walks an infinite plane's tiles along the horizon.
TEST(Shadows, ALightAtTheHorizonDarkensEveryHit) {
    EXPECT_EQ(viewFromAngles(90, 120).z, 0.0);
    EXPECT_EQ(viewFromAngles(90, 90).x, 0.0);
    EXPECT_EQ(viewFromAngles(90, 90).y, 1.0);
    Scene sc = litPlane(test::bricks(32), 0.05, -0.025, 40, 0, 48,
                        R"(["pom", "parallax", {"preset": "tatarchuk_soft"}])");
    sc.plane()->infinite = true;
    sc.camera.frame = Framing::Fill;
    sc.camera.fillSize = 1;
    sc.light = LightSpec{90, 120};
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    for (const TruthSample& t : r.truth.data) EXPECT_EQ(t.shadow, kShadowDark);
    for (const MethodFrame& m : r.methods) {
        EXPECT_EQ(m.stats.shadow.methodDark, m.stats.shadow.compared) << m.config.label;
        EXPECT_EQ(m.stats.shadow.truthDark, m.stats.shadow.compared) << m.config.label;
    }
}

// The hard march's last sample sits exactly at the top of the relief: a point on the floor
// whose light ray leaves the relief exactly over a plateau of the top height grazes it, and is
// lit (the surface is not above the ray there). Adding the step k times in float can end below
// the top, which darkened such points. Seeded scales, biases and floor points; the light is
// set so the 16th sample lands on the plateau and the 15th before it.
TEST(Shadows, TheHardMarchEndsExactlyAtTheTop) {
    const Texture map = test::makeTexture(
        64, 64, [](int i, int) { return i >= 44 ? 1.0 : 0.0; }, Address::Clamp);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    MethodTextureCache cache(map, UvExtent(1.0));
    const MethodConfig pom = test::method(R"("pom")");
    int lit = 0;
    const int n = 2000;
    for (int k = 0; k < n; ++k) {
        const double s = 0.01 + 0.2 * uni(rng), b = -0.25 * uni(rng);
        MethodContext<float> c = makeMethodContext<float>(cache.get(pom, {s, b}));
        const float u0 = float(0.05 + 0.3 * uni(rng));
        // 16 steps of (top - z0) / 16 in height; over all 16 the ray moves 0.7 - u0 in u:
        // the 15th sample at u0 + 15/16 (0.7 - u0) < 0.679 (the floor), the 16th at 0.7.
        const float z0 = float(b), top = float(s + b);
        const float slope = (0.7f - u0) / (top - z0);
        const Vec3f light = glm::normalize(Vec3f(slope, 0, 1));
        lit += hardShadow<float>(c, Vec2f(u0, 0.5f), z0, light, 16) == kShadowLit;
    }
    EXPECT_EQ(lit, n);
}

// Scaling the heights by k and the light's slope above the plane (cot theta_light) by k maps
// every shadow onto itself: seen head-on (the same points visible at every k), the truth's
// shadowed share is the same from k = 1 to 1e-2, the shadow ray starting off the surface by a
// share of the relief, not of the sheet's size. (Below 1e-3 Embree's float test of rays that
// graze triangles at slopes of 1e-4 finds hits that are not there: docs/model.md §5b.)
TEST(Shadows, ScalingTheReliefWithTheLightsSlopeKeepsEveryShadow) {
    const double cot0 = 1.0 / std::tan(60.0 * kPi / 180.0);
    double first = -1;
    for (double k : {1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
        Scene sc = litPlane(test::bricks(32), 0.1 * k, -0.05 * k, 0, 0, 64, R"(["none"])");
        sc.light = LightSpec{std::atan2(1.0, k * cot0) * 180.0 / kPi, 30};
        const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
        int hits = 0, dark = 0;
        for (const TruthSample& t : r.truth.data) {
            hits += t.hit;
            dark += t.hit && t.shadow == kShadowDark;
        }
        ASSERT_GT(hits, 3000);
        const double share = double(dark) / hits;
        std::printf("k %g: shadowed %.4f\n", k, share);
        if (first < 0) first = share;
        EXPECT_GT(share, 0.2);  // the light is low enough to cast shadows at all
        EXPECT_NEAR(share, first, 0.005) << "k " << k;
    }
}

}  // namespace
}  // namespace pgt
