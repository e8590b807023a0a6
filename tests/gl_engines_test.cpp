// The engine presets (docs/methods.md "Engine presets"). Oracles: their closed forms on a flat
// height, the head-on view (a twin's nanHeadOn quirk aside), convergence with their step
// counts, every GLSL preset against its C++ twin (tests/preset_twins.h; 20,000
// fragments), the stiff suite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "frame/render.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/shader/glsl_method.h"
#include "preset_twins.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

GlslRun runPreset(const std::string& name, const Texture& t, const test::Fragments& in,
                  const std::string& uniforms = "") {
    MethodConfig cfg =
        test::method(R"({"preset":")" + name + R"(","amplitude":"shipped")" +
                     (uniforms.empty() ? "" : R"(,"uniforms":{)" + uniforms + "}") + "}");
    EXPECT_EQ(cfg.preset, name);
    return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.025, in.uv0, in.view);
}

// Every GLSL preset (a shader file) fed V, in the preset table's order: those that build V from
// the engine's inputs (their _tangents variants are here) are held on a rendered plane below.
std::vector<std::string> glslPresets() {
    std::vector<std::string> out;
    for (const MethodPreset& p : methodPresets())
        if (!p.shaderFile.empty() && !p.glsl.engineInputs) out.push_back(p.name);
    return out;
}

// Flat height h: jME classic offsets by s (h - 0.6) cos(theta) along unit V.xy; jME steep meets
// its ray exactly (1 - a = (1 - h) / ... on a flat line) unless it stops at the first sample;
// three.js basic offsets by -s h V.xy, occlusion lands where its ray meets depth h exactly.
TEST(Gl, EnginePresetsHaveTheirClosedFormsOnFlatHeight) {
    const double h = 0.3;
    Texture t = test::makeTexture(16, 16, [&](int, int) { return h; });
    test::Fragments in = test::randomFragments(400, 31, 80);
    const GlslRun jme = runPreset("jme", t, in), steep = runPreset("jme_steep", t, in);
    const GlslRun basic = runPreset("threejs_basic_tangents", t, in);
    const GlslRun pc = runPreset("playcanvas_tangents", t, in),
                  pcFixed = runPreset("playcanvas_fixed_tangents", t, in);
    const GlslRun occlusion = runPreset("threejs_occlusion_tangents", t, in);
    const GlslRun ogre = runPreset("ogre_parallax", t, in), ogrePom = runPreset("ogre_pom", t, in);
    const GlslRun o3de = runPreset("o3de_pom", t, in), o3deBasic = runPreset("o3de_basic", t, in);
    const GlslRun dp = runPreset("darkplaces_offset", t, in);
    const GlslRun dpRelief = runPreset("darkplaces_relief", t, in);
    const GlslRun bjs = runPreset("babylon_offset_tangents", t, in);
    const GlslRun bjsPom = runPreset("babylon_occlusion_tangents", t, in);
    const GlslRun ogreFixed = runPreset("ogre_pom_fixed", t, in);
    const GlslRun bjsFixed = runPreset("babylon_occlusion_fixed_tangents", t, in);
    const GlslRun pcLimited = runPreset("playcanvas_offset_limited_tangents", t, in);
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        const Vec2d uv0(in.uv0[k]);
        const Vec3d v = glm::normalize(Vec3d(in.view[k]));
        const Vec2d dir(v.x, v.y);
        EXPECT_LT(glm::length(Vec2d(jme.uv[k]) - (uv0 + dir * 0.05 * (h - 0.6) * v.z)), 1e-6);
        // jME steep: the ray from height 1 at uv0 to 0 at uv0 - P meets h at 1 - h of P.
        const double tanTheta = glm::length(dir) / v.z;
        const Vec2d P = glm::normalize(dir) * tanTheta * 0.015;
        EXPECT_LT(glm::length(Vec2d(steep.uv[k]) - (uv0 - P * (1 - h))), 1e-5 + 1e-5 * tanTheta)
            << k;
        EXPECT_LT(glm::length(Vec2d(basic.uv[k]) - (uv0 + dir * 0.005 * h)), 1e-6);
        // PlayCanvas with mesh tangents (TBN_TANGENTS hands its chunk +V): h' = 0.025 (h - 1/2)
        // along (V.x, V.y) / (V.z + 0.42); the fixed variant's corrected sign along -V.y.
        const double hp = 0.025 * (h - 0.5), z = v.z + 0.42;
        EXPECT_LT(glm::length(Vec2d(pc.uv[k]) - (uv0 + dir * hp / z)), 1e-6);
        EXPECT_LT(glm::length(Vec2d(pcFixed.uv[k]) - (uv0 + Vec2d(v.x, -v.y) * hp / z)), 1e-6);
        // Ogre: uv - V.xy / V.z d s; its occlusion overshoots one layer: uv - (d + 1/32) V.xy s.
        EXPECT_LT(glm::length(Vec2d(ogre.uv[k]) - (uv0 - dir / v.z * (1 - h) * 0.04)),
                  1e-6 + 1e-6 * tanTheta);
        EXPECT_LT(glm::length(Vec2d(ogrePom.uv[k]) - (uv0 - dir * (1 - h + 1.0 / 32) * 0.04)), 1e-6)
            << k;
        // three.js occlusion (its depth is h, the scale -0.005): uv0 + V.xy / V.z 0.005 h.
        EXPECT_LT(glm::length(Vec2d(occlusion.uv[k]) - (uv0 + dir / v.z * 0.005 * h)),
                  1e-6 + 1e-5 * tanTheta)
            << k;
        // O3DE: POM meets depth 1 - h exactly, basic offsets by -V.xy d 0.05.
        const Vec2d below = -dir / v.z * (1 - h);  // the ray's point at depth 1 - h, per unit s
        EXPECT_LT(glm::length(Vec2d(o3de.uv[k]) - (uv0 + below * 0.05)), 1e-6 + 1e-5 * tanTheta);
        EXPECT_LT(glm::length(Vec2d(o3deBasic.uv[k]) - (uv0 - dir * (1 - h) * 0.05)), 1e-6);
        // DarkPlaces: its two steps of O / 2 (1 - h) add up to O (1 - h), O = -0.04 V.xy; relief
        // stops within 1/10 / 2^5 of the height.
        const Vec2d dpWant = uv0 - dir * 0.04 * (1 - h);
        EXPECT_LT(glm::length(Vec2d(dp.uv[k]) - dpWant), 1e-6);
        EXPECT_LT(glm::length(Vec2d(dpRelief.uv[k]) - dpWant),
                  0.04 * glm::length(dir) * (0.1 / 32 + 1e-5) + 1e-6);
        // Babylon with mesh tangents (bumpVertex's TANGENT path hands +V): offset - 0.05 h V.xy;
        // occlusion, toward the eye, reaches depth 1 - h only when its lowest ray height
        // 1 - 14 / (15 + 11 cos(theta)) is below h, else stops 15 steps down.
        EXPECT_LT(glm::length(Vec2d(bjs.uv[k]) - (uv0 - dir * 0.05 * h)), 1e-6);
        // The fixed variants land exactly where their rays meet the flat height: Ogre's at
        // uv - d S (no overshoot), Babylon's at depth 1 - h at every angle.
        EXPECT_LT(glm::length(Vec2d(ogreFixed.uv[k]) - (uv0 - dir * (1 - h) * 0.04)), 1e-6) << k;
        EXPECT_LT(glm::length(Vec2d(bjsFixed.uv[k]) - (uv0 - below * 0.05)), 1e-6 + 1e-5 * tanTheta)
            << k;
        // PlayCanvas beta.20 with mesh tangents: 0.1 (h - 1/2) along (V.x, -V.y) of the unit V
        // (its y flip, right for the derivative frame, is wrong for +V).
        EXPECT_LT(glm::length(Vec2d(pcLimited.uv[k]) - (uv0 + Vec2d(v.x, -v.y) * 0.1 * (h - 0.5))),
                  1e-6);
        const double samples = 15 + 11 * v.z, lowest = 1 - 14 / samples;
        if (std::fabs(lowest - h) > 1e-3) {
            const Vec2d want =
                lowest < h ? uv0 - below * 0.05 : uv0 + dir / v.z * 0.05 * (15 / samples);
            EXPECT_LT(glm::length(Vec2d(bjsPom.uv[k]) - want), 1e-6 + 1e-5 * tanTheta) << k;
        }
    }
}

// Head-on: every preset returns uv0, except jME steep and Babylon's occlusion, whose
// normalize(vec2(0)) is not a number (their quirk: head-on fragments get no finite uv').
TEST(Gl, EnginePresetsHeadOn) {
    Texture t = test::smoothTexture(32, 32);
    test::Fragments in = test::randomFragments(300, 32);
    for (Vec3f& v : in.view) v = Vec3f(0, 0, 1);
    for (const std::string& name : glslPresets()) {
        const PresetTwin* twin = presetTwin(name);
        ASSERT_TRUE(twin) << name;
        const GlslRun r = runPreset(name, t, in);
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            if (twin->nanHeadOn) {
                EXPECT_FALSE(std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y)) << k;
                continue;
            }
            EXPECT_LT(glm::length(Vec2d(r.uv[k]) - Vec2d(in.uv0[k])), 1e-6) << name << k;
        }
    }
}

// three.js's occlusion converges as its layers grow (below its 30-step cap: 29 layers reach
// the bottom), at a scale of -0.1 where its steps are several texels long.
TEST(Gl, ThreeJsOcclusionConvergesWithItsLayers) {
    Texture t = test::bricks(64);
    test::Fragments in = test::randomFragments(2000, 33, 60);
    double previous = INFINITY;
    const GlslRun fine = runPreset("threejs_occlusion_tangents", t, in,
                                   R"("parallax_min_layers":29,"parallax_max_layers":29,)"
                                   R"("parallax_scale":-0.1)");
    for (int layers : {4, 8, 24}) {
        const std::string n = std::to_string(layers);
        const GlslRun r = runPreset("threejs_occlusion_tangents", t, in,
                                    R"("parallax_min_layers":)" + n + R"(,"parallax_max_layers":)" +
                                        n + R"(,"parallax_scale":-0.1)");
        double sum = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k)
            sum += glm::length(Vec2d(r.uv[k]) - Vec2d(fine.uv[k])) * 64;
        const double mean = sum / double(in.uv0.size());
        EXPECT_LT(mean, previous) << layers;
        previous = mean;
    }
    EXPECT_LT(previous, 0.05);
}

// The presets with a step count converge as it grows: O3DE's quality steps, Ogre's layers,
// DarkPlaces' relief steps (each against itself at a far larger count, bricks, views to 70).
TEST(Gl, EnginePresetsConvergeWithTheirStepCounts) {
    Texture t = test::bricks(64);
    test::Fragments in = test::randomFragments(2000, 36, 70);
    struct Knob {
        const char* preset;
        const char* uniform;
        int fine;
    };
    for (const Knob& k :
         {Knob{"o3de_pom", "steps", 256}, Knob{"o3de_relief", "steps", 128},
          Knob{"ogre_pom", "layer_count", 512}, Knob{"darkplaces_relief", "offset_steps", 256}}) {
        auto run = [&](int n) {
            std::string uniforms = "\"";
            uniforms.append(k.uniform).append("\":").append(std::to_string(n));
            return runPreset(k.preset, t, in, uniforms);
        };
        const GlslRun fine = run(k.fine);
        double previous = INFINITY;
        for (int n : {4, 16, 64}) {
            const GlslRun r = run(n);
            double sum = 0;
            for (size_t i = 0; i < in.uv0.size(); ++i)
                sum += glm::length(Vec2d(r.uv[i]) - Vec2d(fine.uv[i])) * 64;
            const double mean = sum / double(in.uv0.size());
            EXPECT_LT(mean, previous) << k.preset << " " << n;
            previous = mean;
        }
        EXPECT_LT(previous, 0.1) << k.preset;
    }
}

// Every GLSL preset's shader against its C++ twin (tests/preset_twins.h) on 20,000
// seeded fragments of the default brick map, views to 85 degrees: at least 99.5% within 1e-3
// texel (a march may flip a step where a float comparison ties). A GLSL preset without a twin
// fails here.
TEST(Gl, EnginePresetsMatchTheirCppTwins) {
    Texture bricks = test::bricks(128);
    test::Fragments in = test::randomFragments(20000, 34);
    int checked = 0;
    for (const std::string& name : glslPresets()) {
        const PresetTwin* twin = presetTwin(name);
        ASSERT_TRUE(twin) << name << " has no C++ twin in tests/preset_twins.cpp";
        const GlslRun gl = runPreset(name, bricks, in);
        int over = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            const Vec2f want = twin->run(bricks, in.uv0[k], in.view[k]);
            const double d = glm::length(Vec2d(gl.uv[k]) - Vec2d(want)) * 128;
            over += !(d <= 1e-3);
        }
        std::printf("%s: %d of 20000 over 1e-3 texel\n", name.c_str(), over);
        EXPECT_LE(over, 100) << name;
        ++checked;
    }
    EXPECT_GE(checked, 29);
}

// Each preset that builds V as its engine does (from screen derivatives, or per vertex) against
// its _tangents variant, rendered on a plane under an orthographic and a pinhole camera: on a
// plane the derivative frames are the base's frame (T, B along the plane's u and v, equal
// lengths) and V per vertex is V per pixel, so both give the same uv' (closed form). Float
// derivatives of float positions move V by about 1e-6: at least 99.5% within 1e-3 texel (a
// march may flip a layer where a comparison ties). Babylon's and PlayCanvas's tangent paths
// hand their functions V with other signs than their derivative paths: there the two differ
// on most pixels (their closed forms are held on a flat height above).
TEST(Gl, EngineFramePresetsEqualTheirTangentsOnAPlane) {
    nlohmann::json methods = nlohmann::json::array();
    auto tangents = [](const std::string& n) {
        return n.size() > 9 && n.compare(n.size() - 9, 9, "_tangents") == 0;
    };
    for (const MethodPreset& p : methodPresets())  // (jme_tangents reads the engine's inputs too)
        if ((p.glsl.engineInputs || p.config.viewPerVertex) && !tangents(p.name))
            methods.push_back({{"preset", p.name}}),
                methods.push_back({{"preset", p.name + "_tangents"}});
    ASSERT_EQ(methods.size(), 2u * 13);
    for (const char* camera :
         {R"({"type": "orthographic", "theta": 55, "phi": 35, "resolution": [64, 64]})",
          R"({"type": "pinhole", "eye": [0.3, -0.9, 0.7], "target": [0, 0, 0], "up": [0, 0, 1],
              "fov": 50, "resolution": [64, 64]})"}) {
        const Scene s = parseScene(
            nlohmann::json::parse(R"({"heightmap": {"procedural": "bricks", "size": [128, 128]},
                "displacement": {"scale": 0.05, "bias": -0.025}, "base": {"type": "plane"},
                "truth": {"rate": 1, "uncertainty": false}, "camera": )" +
                                  std::string(camera) + R"(, "methods": )" + methods.dump() + "}"),
            "test.json");
        const RenderResult r = renderFrame(s, {.timingRepeats = 0});
        for (size_t m = 0; m < r.methods.size(); m += 2) {
            const MethodPreset* preset = nullptr;
            for (const MethodPreset& p : methodPresets())
                if (p.name == r.methods[m + 1].config.preset) preset = &p;
            ASSERT_TRUE(preset);
            const bool signed_ = preset->tangentsSignX != 1 || preset->tangentsSignY != 1;
            const auto& a = r.methods[m].pixels.data;
            const auto& b = r.methods[m + 1].pixels.data;
            int n = 0, over = 0;
            double worst = 0;
            for (size_t k = 0; k < a.size(); ++k) {
                if (!a[k].covered || !b[k].covered) continue;
                const double d = glm::length(a[k].uv - b[k].uv) * 128;
                ++n;
                over += !(d <= 1e-3);
                if (d <= 1e-3) worst = std::max(worst, d);
            }
            std::printf("%s: %d pixels, %d over 1e-3 texel from %s, max within %.2e\n",
                        r.methods[m].config.label.c_str(), n, over,
                        r.methods[m + 1].config.label.c_str(), worst);
            EXPECT_GT(n, 1000);
            if (signed_)
                EXPECT_GT(over, n / 2) << r.methods[m].config.label;
            else
                EXPECT_LE(over, n / 200) << r.methods[m].config.label;
        }
    }
}

// The stiff suite's maps and views (scenes/stress): every preset gives a finite uv' where the
// eye is above the surface (jME steep's head-on NaN aside: the suite has no head-on view).
TEST(Gl, EnginePresetsAreFiniteOnTheStiffSuite) {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::sceneDir() + "/stress")) {
        if (entry.path().extension() != ".json") continue;
        Scene scene = loadScene(entry.path().string());
        test::Fragments in = test::randomFragments(1000, 35);
        const Vec3f v(viewFromAngles(scene.camera.theta, scene.camera.phi));
        if (!(v.z > 0) || scene.camera.theta == 0) continue;
        for (Vec3f& view : in.view) view = v;
        for (const std::string& name : glslPresets()) {
            const GlslRun r = runPreset(name, scene.height, in);
            int bad = 0;
            for (size_t k = 0; k < in.uv0.size(); ++k)
                bad += !(std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y));
            EXPECT_EQ(bad, 0) << entry.path() << " " << name;
        }
        ++scenes;
    }
    EXPECT_GE(scenes, 10);
}

}  // namespace
}  // namespace pgt
