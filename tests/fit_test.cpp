// Fitting: on known surfaces the search finds the parameters that are right by construction.
#include "study/fit.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "frame/render.h"
#include "methods/config.h"
#include "test_util.h"

namespace pgt {
namespace {

Scene fitScene(const std::string& heightmap, const std::string& fit) {
    std::string json = R"({"heightmap": )" + heightmap + R"(,
      "base": {"type": "plane", "infinite": true},
      "displacement": {"scale": 0.06, "bias": -0.03},
      "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [8, 8]},
      "methods": ["parallax"], "truth": {"rate": 2}, "fit": )" +
                       fit + "}";
    return parseScene(nlohmann::json::parse(json), "fit.json");
}

// Constant height c: parallax is exact whenever its own s'*c + b' equals s*c + b, so the best
// objective is ~0 (the listed (s, b) is one such point).
TEST(Fit, ParallaxOnConstantHeightReachesZero) {
    Scene s = fitScene(R"({"procedural": "constant", "value": 0.4, "size": [16, 16]})",
                       R"({"theta": [20, 50, 70], "resolution": [32, 32],
                           "scale_factors": [0.5, 1.5], "bias_ratios": [-1, 0]})");
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 1u);
    EXPECT_LT(r.methods[0].nativeObjective, 1e-3);
    // Neither grid point lies on the line s'c + b' = sc + b; refinement must approach it.
    EXPECT_LT(r.methods[0].bestObjective, 0.05);
    double sb = *r.methods[0].scale * 0.4 + *r.methods[0].bias;
    EXPECT_NEAR(sb, 0.06 * 0.4 - 0.03, 2e-3);
}

// Presets are fixed configurations, and so is a GLSL method whose scale does not reach the
// shader (godot binds none): skipped, the others still fitted.
TEST(Fit, PresetsAndGlslMethodsAreSkipped) {
    Scene s = fitScene(R"({"procedural": "constant", "value": 0.4, "size": [16, 16]})",
                       R"({"theta": [30], "resolution": [16, 16], "scale_factors": [1],
                           "bias_ratios": [-0.5], "refine": 0,
                           "methods": ["parallax", {"preset": "welsh"}, {"preset": "godot"}]})");
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 1u);
    EXPECT_EQ(r.methods[0].method, "parallax");
}

// A smooth field and a dense march: the best own (s, b) is the truth's own (s, b).
TEST(Fit, DensePomRecoversTheTrueScaleAndBias) {
    Scene s = fitScene(R"({"procedural": "sine", "size": [32, 32], "frequency": [2, 3]})",
                       R"({"theta": [30, 50, 65], "resolution": [48, 48], "steps": [64],
                           "scale_factors": [0.5, 0.75, 1.25, 1.5], "bias_ratios": [-0.75, -0.25],
                           "refine": 4,
                           "methods": [{"name": "pom", "layers": 64}]})");
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 1u);
    const FitResult& best = r.methods[0];
    EXPECT_NEAR(*best.scale, 0.06, 0.06 * 0.05) << best.entry().dump();
    EXPECT_NEAR(*best.bias, -0.03, 0.06 * 0.1) << best.entry().dump();
    EXPECT_LE(r.methods[0].bestObjective, r.methods[0].nativeObjective + 1e-9);
}

// An HLSL method is fitted like a built-in: pgt's pom as HLSL (tests/data/hlsl) with its
// height_scale and height_bias bound to s and b and max_layers its "steps_uniform" recovers the
// truth's own (s, b) as the built-in does, and gets the same objective at its best.
TEST(Fit, HlslMethodIsFittedLikeTheBuiltIn) {
    const std::string pom = test::testDataDir() + "/hlsl/pom_twin.hlsl";
    Scene s = fitScene(R"({"procedural": "sine", "size": [32, 32], "frequency": [2, 3]})",
                       R"({"theta": [30, 50, 65], "resolution": [48, 48], "steps": [64],
                           "scale_factors": [0.5, 0.75, 1.25, 1.5], "bias_ratios": [-0.75, -0.25],
                           "refine": 4,
                           "methods": [{"name": "pom", "layers": 64},
                                       {"name": "pom_hlsl", "hlsl": ")" +
                           pom + R"(", "function": "ParallaxOcclusion", "sampler": "heightMap",
                            "steps_uniform": "max_layers",
                            "uniforms": {"height_scale": "scale", "height_bias": "bias",
                                         "min_layers": 64, "max_layers": 8}}]})");
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 2u);
    const auto& builtIn = r.methods[0];
    const auto& hlsl = r.methods[1];
    EXPECT_EQ(hlsl.method, "pom_hlsl");
    EXPECT_EQ(hlsl.steps, 64);
    EXPECT_EQ(hlsl.entry()["uniforms"]["max_layers"], 64) << hlsl.entry().dump();
    EXPECT_NEAR(*hlsl.scale, 0.06, 0.06 * 0.05) << hlsl.entry().dump();
    EXPECT_NEAR(*hlsl.bias, -0.03, 0.06 * 0.1) << hlsl.entry().dump();
    EXPECT_NEAR(hlsl.bestObjective, builtIn.bestObjective, 1e-3 + 0.05 * builtIn.bestObjective);
    std::printf(
        "fit: built-in pom best %.5f at s %.5f b %.5f; HLSL twin best %.5f at s %.5f "
        "b %.5f\n",
        builtIn.bestObjective, *builtIn.scale, *builtIn.bias, hlsl.bestObjective, *hlsl.scale,
        *hlsl.bias);
}

// A call that reads s but not b: the fit varies the scale alone and reports no bias (a "best"
// b would be a number the shader never sees); the same HLSL file called with b gets one.
TEST(Fit, OnlyWhatReachesTheShaderIsFitted) {
    const std::string pom = test::testDataDir() + "/hlsl/pom_twin.hlsl";
    auto entry = [&](const char* name, const char* uniforms) {
        return std::string(R"({"name": ")") + name + R"(", "hlsl": ")" + pom +
               R"(", "function": "ParallaxOcclusion", "sampler": "heightMap", "uniforms": )" +
               uniforms + "}";
    };
    Scene s = fitScene(R"({"procedural": "sine", "size": [32, 32], "frequency": [2, 3]})",
                       R"({"theta": [30, 50], "resolution": [32, 32],
                           "scale_factors": [0.5, 1, 1.5], "bias_ratios": [-0.75, -0.25],
                           "refine": 1, "methods": [)" +
                           entry("scale_only", R"({"height_scale": "scale", "height_bias": -0.03,
                                                    "min_layers": 32, "max_layers": 32})") +
                           ", " + entry("both", R"({"height_scale": "scale", "height_bias": "bias",
                                              "min_layers": 32, "max_layers": 32})") +
                           "]}");
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 2u);
    EXPECT_TRUE(r.methods[0].scale.has_value()) << r.methods[0].entry().dump();
    EXPECT_FALSE(r.methods[0].bias.has_value()) << r.methods[0].entry().dump();
    EXPECT_FALSE(r.methods[0].entry().contains("bias")) << r.methods[0].entry().dump();
    EXPECT_TRUE(r.methods[1].bias.has_value()) << r.methods[1].entry().dump();
    // Each bias ratio of the grid gives the scale-only method the same score: only the
    // scale factors (and the refinement's) are candidates.
    EXPECT_LT(r.methods[0].candidates, r.methods[1].candidates);
}

// The objective is what a render shows: the fitted configuration rendered by `pgt render`'s
// path (renderFrame, a whole scene per view) at the fit's jittered samples and seed scores,
// averaged over the views, the fit's own best mean; at pixel centres (the old default) the
// fit scores another number, and says which samples it used.
TEST(Fit, ObjectiveIsAJitteredRenderAtTheFittedPoint) {
    const char* map = R"({"procedural": "sine", "size": [32, 32], "frequency": [2, 3]})";
    const char* block = R"({"theta": [30, 60], "resolution": [24, 24], "steps": [8],
                            "scale_factors": [0.75, 1.25], "bias_ratios": [-0.75, -0.25],
                            "refine": 1, "seed": 7, %s
                            "methods": [{"name": "pom", "layers": 8}]})";
    auto blockWith = [&](const char* samples) {
        char text[512];
        std::snprintf(text, sizeof text, block, samples);
        return std::string(text);
    };
    Scene s = fitScene(map, blockWith(""));
    FitReport r = runFit(s, false);
    ASSERT_EQ(r.methods.size(), 1u);
    EXPECT_EQ(r.samples, "jittered");
    EXPECT_EQ(r.toJson()["seed"], 7);
    const FitResult& fr = r.methods[0];
    double sum = 0;
    for (double theta : r.thetas) {
        Scene view = s;
        view.methods =
            parseMethods(nlohmann::json::array({fr.entry()}), s.file, "methods", s.worldPerUv());
        view.camera.theta = theta;
        view.camera.width = view.camera.height = 24;
        view.camera.jitter = true, view.camera.jitterSeed = 7;
        sum += renderFrame(view).methods.at(0).stats.error.mean;
    }
    EXPECT_NEAR(fr.bestMean, sum / double(r.thetas.size()), 1e-9 * (1 + fr.bestMean));
    // The same search at pixel centres scores another objective, and records its samples.
    FitReport centre = runFit(fitScene(map, blockWith(R"("samples": "centre",)")), false);
    EXPECT_EQ(centre.samples, "centre");
    EXPECT_FALSE(centre.toJson().contains("seed"));
    EXPECT_GT(std::abs(centre.methods[0].nativeObjective - fr.nativeObjective),
              1e-3 * fr.nativeObjective);
}

TEST(Fit, BadFitBlockNamesTheField) {
    EXPECT_THROW(
        runFit(fitScene(R"({"procedural": "constant"})", R"({"objectiv": "mean"})"), false),
        InputError);
    EXPECT_THROW(runFit(fitScene(R"({"procedural": "constant"})", R"({"theta": [100]})"), false),
                 InputError);
}

}  // namespace
}  // namespace pgt
