// The presets of issue 15 (docs/methods.md "Engine presets"): Unity HDRP's pixel displacement and
// Tatarchuk's POM, each GLSL written from its source. Oracles: their closed forms on a flat
// height, the head-on view, and convergence to the exact first hit (test::firstHit) as their
// sample counts grow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "gl/glsl_method.h"
#include "heightfield/heightfield.h"
#include "methods/config.h"
#include "methods/presets.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

GlslRun runPreset(const std::string& name, const Texture& t, const test::Fragments& in) {
    MethodConfig cfg = test::method(R"({"preset":")" + name + "\"}");
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

// The two presets written again in C++ (float, the shaders' order of operations), as their
// twins: Unity's POM with its FastACosPos step count and secant refinement, Tatarchuk's march.
Vec2f unityTwin(const Texture& t, Vec2f uv, Vec3f V, float amplitude, float lo, float hi) {
    auto height = [&](Vec2f p) { return sampleBilinear<float>(t, p); };
    Vec3f n = glm::normalize(Vec3f(V.x * amplitude, V.y * amplitude, V.z));
    const float x = std::fabs(n.z);
    const float angle = ((0.0468878f * x - 0.203471f) * x + 1.570796f) * std::sqrt(1.0f - x);
    const float unit = std::clamp(angle * (2.0f / 3.14159265358979f), 0.0f, 1.0f);
    const int steps = std::min(int(lo * (1 - unit) + hi * unit), 256);
    const float size = 1.0f / float(steps);
    const Vec2f perStep = size * (Vec2f(n.x, n.y) / -n.z);
    Vec2f now(0.0f);
    float prev = height(uv + now);
    now += perStep;
    float curr = height(uv + now), ray = 1.0f - size;
    for (int i = 0; i < steps && !(curr > ray); ++i) {
        prev = curr;
        ray -= size;
        now += perStep;
        curr = height(uv + now);
    }
    float top = ray + size, bottom = ray, gapTop = top - prev, gapBottom = bottom - curr;
    Vec2f offset = now;
    for (int i = 0; i < 3; ++i) {
        const float hit = (top * gapBottom - bottom * gapTop) / (gapBottom - gapTop);
        offset = (1.0f - hit) * perStep * float(steps);
        const float gap = hit - height(uv + offset);
        if (std::fabs(gap) <= 0.01f) break;
        (gap < 0 ? gapBottom : gapTop) = gap;
        (gap < 0 ? bottom : top) = hit;
    }
    return uv + offset;
}

Vec2f tatarchukTwin(const Texture& t, Vec2f uv, Vec3f V, float scale, float lo, float hi) {
    const Vec2f offset = Vec2f(V.x, V.y) / V.z * scale;
    const int steps = int(hi * (1 - V.z) + lo * V.z);
    const float size = 1.0f / float(steps);
    const Vec2f perStep = size * offset;
    Vec2f current = uv;
    float bound = 1.0f, prev = 1.0f;
    Vec2f pt1(0.0f), pt2(0.0f);
    for (int i = 0; i < steps; ++i) {
        current -= perStep;
        const float h = sampleBilinear<float>(t, current);
        bound -= size;
        if (h > bound) {
            pt1 = Vec2f(bound, h);
            pt2 = Vec2f(bound + size, prev);
            break;
        }
        prev = h;
    }
    const float d2 = pt2.x - pt2.y, d1 = pt1.x - pt1.y, den = d2 - d1;
    const float amount = den == 0.0f ? 0.0f : (pt1.x * d2 - pt2.x * d1) / den;
    return uv - offset * (1.0f - amount);
}

// Each preset's shader against its C++ twin on 20,000 seeded fragments of the default
// scene's brick map, views to 85 degrees: at least 99.5% within 1e-3 texel (a march may
// flip a step where a float comparison ties).
TEST(Gl, UnityAndTatarchukPresetsMatchTheirCppTwins) {
    Texture bricks = test::bricks(128);
    test::Fragments in = test::randomFragments(20000, 24);
    for (const char* name : {"unity_hdrp", "tatarchuk"}) {
        GlslRun gl = runPreset(name, bricks, in);
        int over = 0;
        double largest = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            Vec2f want = std::string(name) == "unity_hdrp"
                             ? unityTwin(bricks, in.uv0[k], in.view[k], 0.02f, 5.0f, 15.0f)
                             : tatarchukTwin(bricks, in.uv0[k], in.view[k], 0.02f, 8.0f, 50.0f);
            const double d = glm::length(Vec2d(gl.uv[k]) - Vec2d(want)) * 128;
            if (!(d <= 1e-3))
                ++over;
            else
                largest = std::max(largest, d);
        }
        std::printf("%s: %d of 20000 over 1e-3 texel, largest within %.2e\n", name, over, largest);
        EXPECT_LE(over, 100) << name;
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
