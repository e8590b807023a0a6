// The stiff suite: methods where V.z is 0 or negative, POM's 0/0, and every
// scenes/stress case through `pgt stress` without a crash or a NaN in a statistic.
#include "study/stress.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "frame/render.h"
#include "methods/registry.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

const char* kAll[] = {R"({"name":"none"})",
                      R"({"name":"parallax"})",
                      R"({"name":"offset_limited"})",
                      R"({"name":"steep"})",
                      R"({"name":"pom"})",
                      R"({"name":"relief"})",
                      R"({"name":"relief","binary_steps":0})",
                      R"({"name":"iterative"})",
                      R"({"name":"tangent_plane"})",
                      R"({"name":"secant"})",
                      R"({"name":"contact"})",
                      R"({"name":"maxmip"})"};

// V in the tangent plane (V.z = 0 exactly) and below it: every method terminates, and its
// result is either finite or non-finite (which the comparator counts and never averages).
TEST(Stress, MethodsTerminateWhenVzIsZeroOrNegative) {
    Texture t = test::smoothTexture(16, 16);
    for (double bias : {-0.05, -0.025, 0.0}) {
        MethodTextures tex = makeMethodTextures(t, 0.05, bias, 1.0, true);
        tex.pyramid = std::make_shared<const MinMaxPyramid>(buildMinMaxPyramid(t));
        for (Vec3f v : {Vec3f(1, 0, 0), Vec3f(0.6f, 0, -0.8f), Vec3f(0, 0, -1)}) {
            for (const char* m : kAll) {
                MethodConfig cfg = test::method(m);
                MethodContext<float> c = makeMethodContext<float>(tex);
                Vec2f uv = runMethod<float>(*cfg.builtin(), c, Vec2f(0.3f, 0.6f), v);
                // Terminated: a march fetches at most its layers + 2 (or the safety cap).
                EXPECT_LE(c.fetches, 64 + 2) << m << " V " << v.x << "," << v.z;
                (void)uv;
            }
        }
    }
}

// POM's bracketing depths equal: with one layer and depths 0.5 then 1.5 (a float map may
// leave [0, 1]), after = before = 0.5, so w = 0.5 / 0. Flagged, non-finite, counted.
TEST(Stress, PomZeroDenominatorIsFlaggedAndCounted) {
    Texture t = test::makeTexture(
        2, 1, [](int i, int) { return i == 0 ? 0.5 : -0.5; }, Address::Clamp);
    MethodTextures tex = makeMethodTextures(t, 0.5, -0.5, 1.0, false);
    MethodConfig cfg = test::method(R"({"name":"pom","layers":1,"max_steps":1})");
    MethodContext<float> c = makeMethodContext<float>(tex);
    // D = V.xy / V.z * s / n = (-1) * 0.5 = -0.5 in u: from texel 0's centre to texel 1's.
    Vec3f v(-std::sqrt(0.5f), 0, std::sqrt(0.5f));
    Vec2f uv = runMethod<float>(*cfg.builtin(), c, Vec2f(0.25f, 0.5f), v);
    EXPECT_TRUE(c.flags & kFlagZeroDivide);
    EXPECT_FALSE(std::isfinite(uv.x) && std::isfinite(uv.y));
    // Through the comparator: counted as non-finite and diverged, statistics stay NaN-free.
    Image2D<TruthSample> truth(1, 1);
    truth.at(0, 0).hit = true;
    truth.at(0, 0).uv = Vec2d(0.25, 0.5);
    Image2D<MethodPixel> px(1, 1);
    MethodPixel& p = px.at(0, 0);
    p.covered = true, p.uv = Vec2d(uv), p.fetches = uint32_t(c.fetches), p.flags = c.flags;
    FrameStats fs = compareWithTruth(truth, px, 2, 1, Address::Clamp);
    EXPECT_EQ(fs.nonfinite, 1);
    EXPECT_EQ(fs.diverged, 1);
    EXPECT_EQ(fs.zeroDivide, 1);
    EXPECT_EQ(fs.error.count, 0);
}

// Every stress scene through `pgt stress` (small resolution): rows for every method, no NaN
// in a statistic of a frame that has pixels, and the known answers of the easy cases.
TEST(Stress, SuiteRunsAndKnownCasesHold) {
    auto dir = test::tempDir("stress");
    StressOptions opt;
    opt.outDir = dir.string();
    opt.resolution = 32;
    opt.precisionSamples = 256;
    opt.progress = false;
    int n = runStress({test::sceneDir() + "/stress"}, opt);
    EXPECT_GE(n, 14);
    std::ifstream in(dir / "stress.csv");
    std::string line;
    std::getline(in, line);
    int rows = 0;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        ASSERT_EQ(f.size(), stressColumns().size()) << line;
        ++rows;
        long pixels = std::stol(f[3]);
        if (pixels > 0) {
            EXPECT_NE(f[10], "nan") << line;  // mean
            EXPECT_NE(f[12], "nan") << line;  // max
        }
        if (f[0] == "scale_zero") {
            EXPECT_LT(std::stod(f[10]), 1e-3) << line;
        }
        if (f[0] == "far_plane" || f[0] == "scale_zero") {
            EXPECT_LT(std::stod(f[15]), 1e-3) << line;  // float truth vs double, texels
        }
        // A 1x1 map is a constant field: parallax, pom, tangent_plane, secant, contact, maxmip and
        // cone are exact there.
        bool exactOnConstant = f[2] == "parallax" || f[2] == "pom" || f[2] == "tangent_plane" ||
                               f[2] == "secant" || f[2] == "contact" || f[2] == "maxmip" ||
                               f[2] == "cone";
        if (f[0] == "map_1x1" && exactOnConstant) {
            EXPECT_LT(std::stod(f[12]), 1e-3) << line;
        }
    }
    // A row per scene and listed method; every scene lists every built-in (docs/studies.md).
    int listed = 0;
    for (const auto& e : std::filesystem::directory_iterator(test::sceneDir() + "/stress")) {
        if (e.path().extension() != ".json") continue;
        const Scene scene = loadScene(e.path().string());
        listed += int(scene.methods.size());
        std::set<MethodKind> kinds;
        for (const MethodConfig& m : scene.methods)
            if (const BuiltinMethod* b = m.builtin()) kinds.insert(b->kind);
        for (const MethodKindInfo& k : methodKinds())
            EXPECT_TRUE(kinds.count(k.kind)) << e.path() << " lacks " << k.name;
    }
    EXPECT_EQ(rows, listed);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pgt
