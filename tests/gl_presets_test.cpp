// The Unity HDRP and Tatarchuk presets (docs/methods.md "Engine presets"): Unity HDRP's pixel
// displacement and Tatarchuk's POM, each GLSL written from its source. Oracles: their closed forms
// on a flat height, the head-on view, and convergence to the exact first hit (test::firstHit) as
// their sample counts grow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "heightfield/heightfield.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/shader/glsl_method.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

GlslRun runPreset(const std::string& name, const Texture& t, const test::Fragments& in) {
    MethodConfig cfg = test::method(R"({"preset":")" + name + R"(","amplitude":"shipped"})");
    EXPECT_EQ(cfg.preset, name);
    return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.025, in.uv0, in.view);
}

// A preset's shader with its sample counts set to n (min = max).
GlslRun runWithSamples(const std::string& file, const std::string& function,
                       const std::string& uniforms, const Texture& t, const test::Fragments& in) {
    MethodConfig cfg = test::method(R"({"name":"p","glsl":")" + shaderDir() + "/presets/" + file +
                                    R"(","function":")" + function +
                                    R"(","sampler":"heightMap","uniforms":{)" + uniforms + "}}");
    return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.025, in.uv0, in.view);
}

// On a flat height h both land exactly where the ray meets it: uv0 - V.xy / V.z * A (1 - h),
// A = 0.02 (Unity's secant and Tatarchuk's line intersection are exact on a flat line).
TEST(Gl, UnityAndTatarchukPresetsHaveTheirClosedFormsOnFlatHeight) {
    const double h = 0.3, amplitude = 0.02;
    Texture t = test::makeTexture(16, 16, [&](int, int) { return h; });
    test::Fragments in = test::randomFragments(400, 21);
    GlslRun unity = runPreset("unity_hdrp", t, in), tatarchuk = runPreset("tatarchuk", t, in);
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        Vec2d uv0(in.uv0[k]);
        Vec3d v(in.view[k]);
        Vec2d want = uv0 - Vec2d(v.x, v.y) / v.z * amplitude * (1 - h);
        double tol = 1e-6 + 1e-5 * glm::length(want - uv0);
        EXPECT_LT(glm::length(Vec2d(unity.uv[k]) - want), tol) << k;
        EXPECT_LT(glm::length(Vec2d(tatarchuk.uv[k]) - want), tol) << k;
        EXPECT_GE(unity.fetches[k], 3u);  // two before the loop, one secant step at least
        EXPECT_GE(tatarchuk.fetches[k], 1u);
    }
}

TEST(Gl, UnityAndTatarchukPresetsReturnUv0HeadOn) {
    Texture t = test::smoothTexture(32, 32);
    test::Fragments in = test::randomFragments(300, 22);
    for (Vec3f& v : in.view) v = Vec3f(0, 0, 1);
    for (const char* name : {"unity_hdrp", "tatarchuk"}) {
        GlslRun r = runPreset(name, t, in);
        for (size_t k = 0; k < in.uv0.size(); ++k) EXPECT_EQ(r.uv[k], in.uv0[k]) << name << k;
    }
}

// Both with min = max = n samples, n = 4, 16, 64, at A = 0.05 (the shaders' own amplitude
// uniform) on a smooth map, views to 70 degrees: the mean distance to the exact first hit
// shrinks with n. Their relief is s = A, b = -A.
TEST(Gl, UnityAndTatarchukPresetsConvergeWithSamples) {
    Texture t = test::smoothTexture(64, 64);
    test::Fragments in = test::randomFragments(2000, 23, 70);
    const double amplitude = 0.05;
    std::vector<Vec2d> exact;
    for (size_t k = 0; k < in.uv0.size(); ++k)
        exact.push_back(
            test::firstHit(t, amplitude, -amplitude, Vec2d(in.uv0[k]), Vec3d(in.view[k])));
    auto meanError = [&](const GlslRun& r) {
        double sum = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k)
            sum += glm::length(Vec2d(r.uv[k]) - exact[k]) * t.width;
        return sum / double(in.uv0.size());
    };
    for (int variant = 0; variant < 2; ++variant) {
        std::vector<double> errors;
        for (int n : {4, 16, 64}) {
            const std::string ns = std::to_string(n) + ".0";
            GlslRun r = variant == 0
                            ? runWithSamples("unity_hdrp.glsl", "UnityHdrpPom",
                                             R"("height_amplitude":0.05,"ppd_min_samples":)" + ns +
                                                 R"(,"ppd_max_samples":)" + ns,
                                             t, in)
                            : runWithSamples("tatarchuk.glsl", "TatarchukPom",
                                             R"("height_map_scale":0.05,"min_samples":)" + ns +
                                                 R"(,"max_samples":)" + ns,
                                             t, in);
            errors.push_back(meanError(r));
        }
        std::printf("variant %d: mean texels %.4g %.4g %.4g\n", variant, errors[0], errors[1],
                    errors[2]);
        EXPECT_LT(errors[1], errors[0]) << variant;
        EXPECT_LT(errors[2], errors[1]) << variant;
        EXPECT_LT(errors[2], 0.05) << variant;
    }
}

// The stiff suite's maps and views (scenes/stress): both presets give a finite uv' on every
// fragment (their step counts are bounded; Tatarchuk's zero denominator gives amount 0).
TEST(Gl, UnityAndTatarchukPresetsAreFiniteOnTheStiffSuite) {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::sceneDir() + "/stress")) {
        if (entry.path().extension() != ".json") continue;
        Scene scene = loadScene(entry.path().string());
        test::Fragments in = test::randomFragments(2000, 25);
        const Vec3f v(viewFromAngles(scene.camera.theta, scene.camera.phi));
        if (!(v.z > 0)) continue;  // grazing_90: no fragment faces the eye
        for (Vec3f& view : in.view) view = v;
        for (const char* name : {"unity_hdrp", "tatarchuk"}) {
            GlslRun r = runPreset(name, scene.height, in);
            for (size_t k = 0; k < in.uv0.size(); ++k)
                ASSERT_TRUE(std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y))
                    << entry.path() << " " << name << " " << k;
        }
        ++scenes;
    }
    EXPECT_GE(scenes, 13);
}

// Bevy does not clamp |V.z| (its parallax_mapping.wgsl divides by abs(Vt.z)): at V.z = 0 the
// offset is infinite or NaN. The draw survives and uv' is non-finite, which the comparator
// counts as a divergence; just above 0 the march stays bounded (at most layers + 1 steps).
TEST(Gl, BevyAtGrazingZeroDivergesWithoutACrash) {
    Texture t = test::smoothTexture(32, 32);
    test::Fragments in = test::randomFragments(64, 26);
    for (size_t k = 0; k < in.view.size(); ++k)
        in.view[k] = k % 2 ? Vec3f(0.6f, 0.8f, 0.0f) : Vec3f(viewFromAngles(89.99, 40));
    for (const char* name : {"bevy_occlusion", "bevy_relief"}) {
        GlslRun r = runPreset(name, t, in);
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            const bool finite = std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y);
            EXPECT_EQ(finite, k % 2 == 0) << name << " " << k;
            EXPECT_LE(r.fetches[k], 19u) << name << " " << k;  // 16 layers + 2, + relief's 5
        }
    }
}

}  // namespace
}  // namespace pgt
