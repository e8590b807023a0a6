// The refined searches (secant, contact) against closed forms and an independent first-hit
// oracle: exact where the height is linear along the ray, converging as steps grow.
#include <gtest/gtest.h>

#include <random>

#include "frame/render.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

using test::makeTexture;
using test::method;

Vec2f runOne(const MethodConfig& cfg, const MethodTextures& tex, Vec2d uv0, Vec3d v,
             int* fetches = nullptr) {
    MethodContext<float> c = makeMethodContext<float>(tex);
    Vec2f uv = runMethod<float>(*cfg.builtin(), c, Vec2f(uv0), Vec3f(v));
    if (fetches) *fetches = c.fetches;
    return uv;
}

// h linear in u (clamp, rays kept inside the texel centres): the bilinear height is the
// same line, so the depth along the ray is linear in t. The secant through any bracket hits
// the root exactly; contact's final interpolation is pom's, exact on a straight line.
TEST(Searches, ExactOnARamp) {
    const int w = 64;
    Texture t = makeTexture(
        w, 8, [&](int i, int) { return 0.2 + 0.6 * (i + 0.5) / w; }, Address::Clamp);
    const double s = 0.05, b = -0.03;
    MethodTextures tex = makeMethodTextures(t, s, b, 1.0, false);
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (const char* m : {R"({"name":"secant","linear_steps":6,"secant_steps":1})",
                          R"({"name":"contact","layers":5})"}) {
        MethodConfig cfg = method(m);
        for (int k = 0; k < 200; ++k) {
            Vec2d uv0(0.3 + 0.4 * uni(rng), 0.3 + 0.4 * uni(rng));
            Vec3d v = viewFromAngles(70 * uni(rng), 360 * uni(rng));
            // Closed form: z = s * (0.2 + 0.6 * u(z)) + b with u(z) = u0 + dx * z.
            const double dx = v.x / v.z, dy = v.y / v.z;
            const double z = (s * (0.2 + 0.6 * uv0.x) + b) / (1.0 - s * 0.6 * dx);
            const Vec2d want = uv0 + Vec2d(dx, dy) * z;
            Vec2f got = runOne(cfg, tex, uv0, v);
            EXPECT_NEAR(got.x, want.x, 2e-6) << m << " case " << k;
            EXPECT_NEAR(got.y, want.y, 2e-6) << m << " case " << k;
        }
    }
}

// Mean distance (texels) to the first-hit oracle over seeded fragments of a smooth map.
double meanError(const MethodConfig& cfg, const Texture& t, double s, double b, double theta) {
    MethodTextures tex = makeMethodTextures(t, s, b, 1.0, false);
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double sum = 0;
    const int n = 400;
    for (int k = 0; k < n; ++k) {
        Vec2d uv0(uni(rng), uni(rng));
        Vec3d v = viewFromAngles(theta, 360 * uni(rng));
        Vec2d want = test::firstHit(t, s, b, uv0, v);
        Vec2f got = runOne(cfg, tex, uv0, v);
        sum += std::hypot((got.x - want.x) * t.width, (got.y - want.y) * t.height);
    }
    return sum / n;
}

// More steps never hurt on a smooth map, and the finest setting is well under a texel.
TEST(Searches, MoreStepsConvergeToTheFirstHit) {
    Texture t = test::smoothTexture(64, 64);
    for (double theta : {45.0, 70.0}) {
        double prevSecant = 1e9, prevContact = 1e9;
        for (int steps : {4, 8, 16, 32}) {
            MethodConfig sec = method(R"({"name":"secant","secant_steps":3})");
            MethodConfig con = method(R"({"name":"contact"})");
            setStepCount(sec, steps);
            setStepCount(con, steps);
            double es = meanError(sec, t, 0.08, -0.04, theta);
            double ec = meanError(con, t, 0.08, -0.04, theta);
            EXPECT_LE(es, prevSecant * 1.05 + 1e-4) << "secant " << steps << " theta " << theta;
            EXPECT_LE(ec, prevContact * 1.05 + 1e-4) << "contact " << steps << " theta " << theta;
            prevSecant = es, prevContact = ec;
        }
        EXPECT_LT(prevSecant, 0.01) << theta;
        EXPECT_LT(prevContact, 0.01) << theta;
    }
}

// Fetch counts on constant depth d = 0.65 (between layers): secant's linear search takes
// its first sample (t = 0) and ceil(0.65 * n) more, then one per secant step; contact takes
// ceil(d n) + 1 coarse fetches, the re-fetch after the step back, the fine march's steps
// and pom's one extra fetch.
TEST(Searches, FetchCounts) {
    Texture t = makeTexture(8, 8, [](int, int) { return 0.35; });
    MethodTextures tex = makeMethodTextures(t, 0.05, -0.05, 1.0, false);
    Vec3d v = viewFromAngles(50, 20);
    int fetches = 0;
    runOne(method(R"({"name":"secant","linear_steps":10,"secant_steps":3})"), tex, {0.5, 0.5}, v,
           &fetches);
    EXPECT_EQ(fetches, 1 + 7 + 3);
    runOne(method(R"({"name":"contact","layers":10})"), tex, {0.5, 0.5}, v, &fetches);
    // Coarse: 1 + 7 (stops at layer 0.7). Fine, from layer 0.6 by 0.01: 1 + 5 (0.65 is
    // reached within float rounding at the 5th step or the 6th).
    EXPECT_GE(fetches, 8 + 1 + 5 + 1);
    EXPECT_LE(fetches, 8 + 1 + 6 + 1);
}

// Each kind's parameters at the settings of its source (docs/methods.md), from its own struct:
// kinds that share a field's meaning no longer share a field.
TEST(Searches, DefaultsAreTheSources) {
    auto builtin = [](const char* name) {
        return *method(std::string(R"({"name":")") + name + "\"}").builtin();
    };
    const auto sec = builtin("secant").as<SecantParameters>();
    EXPECT_EQ(sec.linearSteps, 10);  // Risser et al. 2007
    EXPECT_EQ(sec.secantSteps, 3);
    EXPECT_EQ(builtin("contact").as<ContactParameters>().layers, 16);  // Riccardi 2018
    const auto pom = builtin("pom").as<LayerParameters>();
    EXPECT_EQ(pom.minLayers, 8);  // LearnOpenGL
    EXPECT_EQ(pom.maxLayers, 32);
    EXPECT_EQ(pom.maxSteps, 0);
    const auto relief = builtin("relief").as<ReliefParameters>();
    EXPECT_EQ(relief.linearSteps, 10);  // Policarpo et al. 2005
    EXPECT_EQ(relief.binarySteps, 5);
    EXPECT_EQ(builtin("iterative").as<IterationParameters>().iterations, 4);
    const auto cone = builtin("cone").as<ConeParameters>();
    EXPECT_EQ(cone.steps, 32);  // Dummer 2006; pgt's 5 bisections
    EXPECT_EQ(cone.refineSteps, 5);
    const auto relaxed = builtin("relaxed_cone").as<RelaxedConeParameters>();
    EXPECT_EQ(relaxed.coneSteps, 15);  // Policarpo & Oliveira 2007, listing 18-3
    EXPECT_EQ(relaxed.binarySteps, 6);
    EXPECT_EQ(builtin("maxmip").as<MaxMipParameters>().maxIterations, 4096);
    // A kind's struct is its own: reading another kind's is refused, not a silent default.
    EXPECT_THROW((void)builtin("cone").as<RelaxedConeParameters>(), std::bad_variant_access);
}

}  // namespace
}  // namespace pgt
