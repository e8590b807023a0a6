// The engine presets of issue 31 so far (docs/methods.md "Engine presets"): jMonkeyEngine 3's
// classic and steep parallax, three.js r131's ParallaxShader modes. Oracles: their closed forms
// on a flat height, the head-on view, convergence of three.js's march with its layers, C++
// twins written from the same reading (20,000 fragments), the stiff suite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "gl/glsl_method.h"
#include "methods/config.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

GlslRun runPreset(const std::string& name, const Texture& t, const test::Fragments& in,
                  const std::string& uniforms = "") {
    MethodConfig cfg =
        test::method(R"({"preset":")" + name + "\"" +
                     (uniforms.empty() ? "" : R"(,"uniforms":{)" + uniforms + "}") + "}");
    EXPECT_EQ(cfg.preset, name);
    return runGlsl(*cfg.shader(), MapRefs{.height = &t}, 0.05, -0.025, in.uv0, in.view);
}

// The twins: float, the shaders' order of operations.
float height(const Texture& t, Vec2f uv) { return sampleBilinear<float>(t, uv); }

Vec2f jmeTwin(const Texture& t, Vec2f uv, Vec3f V, float s) {
    const Vec3f n = glm::normalize(V);
    const float d = (height(t, uv) * s - 0.6f * s) * n.z;
    return uv + d * Vec2f(n.x, n.y);
}

Vec2f jmeSteepTwin(const Texture& t, Vec2f uv, Vec3f V, float s) {
    const float tanTheta = std::sqrt(glm::dot(V, V) - V.z * V.z) / V.z;
    const float scale = 0.3f * s;
    const Vec2f P = glm::normalize(Vec2f(V.x, V.y)) * tanTheta * scale;
    const float samples = glslMix(6.0f, 1000.0f * scale, 1.0f - glm::normalize(V).z);
    const float delta = 1.0f / samples;
    float current = 0, previous = 0, bound = 1;
    Vec2f c = uv;
    for (float k = 0; k < samples && current <= bound; k += 1) {
        c -= delta * P;
        previous = current;
        current = height(t, c);
        bound -= delta;
    }
    const float d2 = (bound + delta) - previous, d1 = bound - current;
    const float amount = (bound * d2 - (bound + delta) * d1) / (d2 - d1);
    return uv - P * (1.0f - amount);
}

// PlayCanvas: h' = h s - s / 2; to beta.19 along (V.x, +-V.y) / (V.z + 0.42), beta.20 along the
// unit V (offset limiting).
Vec2f playcanvasTwin(const Texture& t, Vec2f uv, Vec3f V, float s, float ySign, bool limited) {
    const float h = height(t, uv) * s - s * 0.5f;
    if (limited) {
        const Vec3f v = glm::normalize(V);
        return uv + h * Vec2f(v.x, v.y);
    }
    Vec3f v(V.x, ySign * V.y, V.z);
    v.z += 0.42f;
    return uv + h * Vec2f(v.x, v.y) / v.z;
}

// Ogre: depth 1 - h; parallax uv - V.xy / V.z d s; occlusion S = V.xy s in n steps, each
// moving before comparing the previous layer (strict), then the interpolation.
Vec2f ogreTwin(const Texture& t, Vec2f uv, Vec3f V, float s, int n, bool occlusion) {
    auto depth = [&](Vec2f p) { return 1.0f - height(t, p); };
    const Vec3f e = glm::normalize(V);
    if (!occlusion) return uv - Vec2f(e.x, e.y) / e.z * depth(uv) * s;
    const float L = 1.0f / float(n);
    const Vec2f delta = Vec2f(e.x, e.y) * s / float(n);
    Vec2f current = uv;
    float d = 0, layer = 0;
    for (int i = 0; i < n; ++i) {
        current = uv - float(i + 1) * delta;
        d = depth(current);
        if (float(i) * L > d) break;
        layer = float(i + 1) * L;
    }
    const Vec2f prev = current + delta;
    const float after = d - layer, before = depth(prev) - layer + L;
    const float w = after / (after - before);
    return current * (1.0f - w) + prev * w;
}

// O3DE: depth 1 - h; the march P(t) = -V / V.z t factor in steps of 1/N while depth > t.
enum class O3de { Basic, Steep, Pom, Relief, Contact };
Vec2f o3deTwin(const Texture& t, Vec2f uv, Vec3f V, O3de mode, float factor, int n) {
    auto depth = [&](Vec2f p) { return 1.0f - height(t, p); };
    const Vec3f v = glm::normalize(V);
    if (mode == O3de::Basic) return uv - Vec2f(v.x, v.y) * depth(uv) * factor;
    float step = 1.0f / float(n), tt = 0;
    Vec3f delta = -v * factor / v.z * step, P(0.0f);
    float s = depth(uv), prev = s;
    while (s > tt) {
        tt += step;
        P += delta;
        prev = s;
        s = depth(uv + Vec2f(P));
    }
    if (tt > 0 && mode == O3de::Pom) {
        const float prevDiff = prev - (tt - step), curDiff = tt - s;
        const float w = prevDiff / (prevDiff + curDiff);
        P = (P - delta) * (1.0f - w) + P * w;
    } else if (tt > 0 && mode == O3de::Relief) {
        for (int i = 0; i < n; ++i) {
            delta *= 0.5f;
            step *= 0.5f;
            const float sigma = s > tt ? 1.0f : s < tt ? -1.0f : 0.0f;
            P += sigma * delta;
            tt += sigma * step;
            s = depth(uv + Vec2f(P));
        }
    } else if (tt > 0 && mode == O3de::Contact) {
        P -= delta;
        tt -= step;
        s = prev;
        const Vec3f fine = delta * step;
        const float fineStep = step * step;
        while (s > tt) {
            tt += fineStep;
            P += fine;
            s = depth(uv + Vec2f(P));
        }
    }
    return P.z > 0 ? uv : uv + Vec2f(P);
}

// DarkPlaces: O = -0.04 normalize(V).xy; offset mapping N times tc += O / N (1 - b - h(tc));
// relief the ray (O, -1) / N, N - 1 steps while z >= h, then R refinements of +-f/2.
Vec2f darkplacesTwin(const Texture& t, Vec2f uv, Vec3f V, bool relief, int n, int r) {
    const Vec3f e = glm::normalize(V);
    const Vec2f O = -Vec2f(e.x, e.y) * 0.04f;
    if (!relief) {
        Vec2f tc = uv;
        for (int i = 0; i < n; ++i) tc += O / float(n) * (1.0f - height(t, tc));
        return tc;
    }
    Vec3f step(O, -1.0f), RT(uv, 1.0f);
    step /= float(n);
    auto above = [&]() { return RT.z >= height(t, Vec2f(RT)) ? 1.0f : 0.0f; };
    for (int i = 1; i < n; ++i) RT += step * above();
    float f = 1;
    for (int i = 0; i < r; ++i) {
        RT += step * (f * above() - 0.5f * f);
        f *= 0.5f;
    }
    return Vec2f(RT);
}

// Babylon: offset uv + 0.05 h V.xy; occlusion away from the eye, 15 + 11 cos(theta) samples
// as a float, 15 passes, the linear crossing at the first height above the ray.
Vec2f babylonTwin(const Texture& t, Vec2f uv, Vec3f V, bool occlusion) {
    const Vec3f v = glm::normalize(V);
    if (!occlusion) return uv + 0.05f * height(t, uv) * Vec2f(v.x, v.y);
    const Vec2f maxOff =
        -glm::normalize(Vec2f(v.x, v.y)) * (0.05f * glm::length(Vec2f(v.x, v.y)) / v.z);
    const float samples = 15.0f + glm::dot(-v, Vec3f(0, 0, 1)) * (4.0f - 15.0f);
    const float step = 1.0f / samples;
    float ray = 1, prevHeight = 1;
    Vec2f cur(0.0f), prevOff(0.0f);
    for (int i = 0; i < 15; ++i) {
        const float h = height(t, uv + cur);
        if (h > ray) {
            const float d1 = h - ray, d2 = (ray + step) - prevHeight, q = d1 / (d1 + d2);
            cur = q * prevOff + (1.0f - q) * cur;
            break;
        }
        ray -= step;
        prevOff = cur;
        cur += step * maxOff;
        prevHeight = h;
    }
    return uv + cur;
}

// The _fixed variants' twins: jME steep with no offset head-on; Ogre's occlusion comparing each
// step at its own layer; Babylon's occlusion with mix(15, 4, cos) samples and as many passes.
Vec2f jmeSteepFixedTwin(const Texture& t, Vec2f uv, Vec3f V, float s) {
    return V.x == 0 && V.y == 0 ? uv : jmeSteepTwin(t, uv, V, s);
}

Vec2f ogreFixedTwin(const Texture& t, Vec2f uv, Vec3f V, float s, int n) {
    auto depth = [&](Vec2f p) { return 1.0f - height(t, p); };
    const Vec3f e = glm::normalize(V);
    const float L = 1.0f / float(n);
    const Vec2f delta = Vec2f(e.x, e.y) * s / float(n);
    Vec2f current = uv;
    float d = depth(uv), layer = 0;
    for (int i = 0; i < n && layer < d; ++i) {
        current = uv - float(i + 1) * delta;
        d = depth(current);
        layer = float(i + 1) * L;
    }
    if (layer == 0) return uv;
    const Vec2f prev = current + delta;
    const float after = d - layer, before = depth(prev) - layer + L;
    const float w = after / (after - before);
    return current * (1.0f - w) + prev * w;
}

Vec2f babylonFixedTwin(const Texture& t, Vec2f uv, Vec3f V) {
    const Vec3f v = glm::normalize(V);
    if (v.x == 0 && v.y == 0) return uv;
    const Vec2f maxOff = -Vec2f(v.x, v.y) / v.z * 0.05f;
    const float samples = glslMix(15.0f, 4.0f, v.z);
    const int passes = int(std::ceil(samples));
    const float step = 1.0f / samples;
    float ray = 1, prevHeight = 1;
    Vec2f cur(0.0f), prevOff(0.0f);
    for (int i = 0; i <= passes; ++i) {
        const float h = height(t, uv + cur);
        if (h > ray) {
            const float d1 = h - ray, d2 = (ray + step) - prevHeight, q = d1 / (d1 + d2);
            return uv + q * prevOff + (1.0f - q) * cur;
        }
        ray -= step;
        prevOff = cur;
        cur += step * maxOff;
        prevHeight = h;
    }
    return uv + cur;
}

enum class Three { Basic, Steep, Occlusion, Relief };

Vec2f threeTwin(const Texture& t, Vec2f uv, Vec3f V, Three mode, float s, float lo, float hi) {
    if (mode == Three::Basic) return uv - Vec2f(V.x, V.y) * height(t, uv) * s;
    const float layers = glslMix(hi, lo, std::fabs(V.z));
    const float layerHeight = 1.0f / layers;
    const Vec2f step = s * Vec2f(V.x, V.y) / V.z / layers;
    Vec2f c = uv;
    float layer = 0, depth = height(t, c);
    for (int i = 0; i < 30; ++i) {
        if (depth <= layer) break;
        layer += layerHeight;
        c -= step;
        depth = height(t, c);
    }
    if (mode == Three::Steep) return c;
    if (mode == Three::Occlusion) {
        const Vec2f prev = c + step;
        const float next = depth - layer;
        const float before = height(t, prev) - layer + layerHeight;
        const float w = next / (next - before);
        return w * prev + (1.0f - w) * c;
    }
    Vec2f d = step * 0.5f;
    float dl = layerHeight * 0.5f;
    c += d;
    layer -= dl;
    for (int i = 0; i < 5; ++i) {
        d *= 0.5f;
        dl *= 0.5f;
        if (height(t, c) > layer)
            c -= d, layer += dl;
        else
            c += d, layer -= dl;
    }
    return c;
}

struct Engine {
    const char* preset;
    std::function<Vec2f(const Texture&, Vec2f, Vec3f)> twin;
};
std::vector<Engine> engines() {
    auto o3de = [](O3de mode) {
        return [mode](const Texture& t, Vec2f uv, Vec3f v) {
            return o3deTwin(t, uv, v, mode, 0.05f, 16);
        };
    };
    auto three = [](Three mode) {
        return [mode](const Texture& t, Vec2f uv, Vec3f v) {
            return threeTwin(t, uv, v, mode, -0.005f, 20.0f, 25.0f);
        };
    };
    return {
        {"jme", [](const Texture& t, Vec2f uv, Vec3f v) { return jmeTwin(t, uv, v, 0.05f); }},
        {"jme_steep",
         [](const Texture& t, Vec2f uv, Vec3f v) { return jmeSteepTwin(t, uv, v, 0.05f); }},
        {"playcanvas", [](const Texture& t, Vec2f uv,
                          Vec3f v) { return playcanvasTwin(t, uv, v, 0.025f, -1.0f, false); }},
        {"playcanvas_fixed", [](const Texture& t, Vec2f uv,
                                Vec3f v) { return playcanvasTwin(t, uv, v, 0.025f, 1.0f, false); }},
        {"playcanvas_offset_limited",
         [](const Texture& t, Vec2f uv, Vec3f v) {
             return playcanvasTwin(t, uv, v, 0.1f, 1.0f, true);
         }},
        {"ogre_parallax",
         [](const Texture& t, Vec2f uv, Vec3f v) { return ogreTwin(t, uv, v, 0.04f, 32, false); }},
        {"ogre_pom",
         [](const Texture& t, Vec2f uv, Vec3f v) { return ogreTwin(t, uv, v, 0.04f, 32, true); }},
        {"o3de_pom", o3de(O3de::Pom)},
        {"o3de_steep", o3de(O3de::Steep)},
        {"o3de_relief", o3de(O3de::Relief)},
        {"o3de_contact", o3de(O3de::Contact)},
        {"o3de_basic", o3de(O3de::Basic)},
        {"darkplaces_offset",
         [](const Texture& t, Vec2f uv, Vec3f v) { return darkplacesTwin(t, uv, v, false, 2, 0); }},
        {"darkplaces_relief",
         [](const Texture& t, Vec2f uv, Vec3f v) { return darkplacesTwin(t, uv, v, true, 10, 5); }},
        {"babylon_offset",
         [](const Texture& t, Vec2f uv, Vec3f v) { return babylonTwin(t, uv, v, false); }},
        {"babylon_occlusion",
         [](const Texture& t, Vec2f uv, Vec3f v) { return babylonTwin(t, uv, v, true); }},
        {"jme_steep_fixed",
         [](const Texture& t, Vec2f uv, Vec3f v) { return jmeSteepFixedTwin(t, uv, v, 0.05f); }},
        {"ogre_pom_fixed",
         [](const Texture& t, Vec2f uv, Vec3f v) { return ogreFixedTwin(t, uv, v, 0.04f, 32); }},
        {"babylon_occlusion_fixed",
         [](const Texture& t, Vec2f uv, Vec3f v) { return babylonFixedTwin(t, uv, v); }},
        {"threejs_basic", three(Three::Basic)},
        {"threejs_steep", three(Three::Steep)},
        {"threejs_occlusion", three(Three::Occlusion)},
        {"threejs_relief", three(Three::Relief)}};
}

// Flat height h: jME classic offsets by s (h - 0.6) cos(theta) along unit V.xy; jME steep meets
// its ray exactly (1 - a = (1 - h) / ... on a flat line) unless it stops at the first sample;
// three.js basic offsets by -s h V.xy, occlusion lands where its ray meets depth h exactly.
TEST(Gl, EnginePresetsHaveTheirClosedFormsOnFlatHeight) {
    const double h = 0.3;
    Texture t = test::makeTexture(16, 16, [&](int, int) { return h; });
    test::Fragments in = test::randomFragments(400, 31, 80);
    const GlslRun jme = runPreset("jme", t, in), steep = runPreset("jme_steep", t, in);
    const GlslRun basic = runPreset("threejs_basic", t, in);
    const GlslRun pc = runPreset("playcanvas", t, in),
                  pcFixed = runPreset("playcanvas_fixed", t, in);
    const GlslRun occlusion = runPreset("threejs_occlusion", t, in);
    const GlslRun ogre = runPreset("ogre_parallax", t, in), ogrePom = runPreset("ogre_pom", t, in);
    const GlslRun o3de = runPreset("o3de_pom", t, in), o3deBasic = runPreset("o3de_basic", t, in);
    const GlslRun dp = runPreset("darkplaces_offset", t, in);
    const GlslRun dpRelief = runPreset("darkplaces_relief", t, in);
    const GlslRun bjs = runPreset("babylon_offset", t, in);
    const GlslRun bjsPom = runPreset("babylon_occlusion", t, in);
    const GlslRun ogreFixed = runPreset("ogre_pom_fixed", t, in);
    const GlslRun bjsFixed = runPreset("babylon_occlusion_fixed", t, in);
    const GlslRun pcLimited = runPreset("playcanvas_offset_limited", t, in);
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
        // PlayCanvas: h' = 0.025 (h - 1/2) along (V.x, -V.y) / (V.z + 0.42); fixed: +V.y.
        const double hp = 0.025 * (h - 0.5), z = v.z + 0.42;
        EXPECT_LT(glm::length(Vec2d(pc.uv[k]) - (uv0 + Vec2d(v.x, -v.y) * hp / z)), 1e-6);
        EXPECT_LT(glm::length(Vec2d(pcFixed.uv[k]) - (uv0 + dir * hp / z)), 1e-6);
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
        // Babylon: offset + 0.05 h V.xy; occlusion reaches depth 1 - h only when its lowest ray
        // height 1 - 14 / (15 + 11 cos(theta)) is below h, else stops 15 steps down.
        EXPECT_LT(glm::length(Vec2d(bjs.uv[k]) - (uv0 + dir * 0.05 * h)), 1e-6);
        // The fixed variants land exactly where their rays meet the flat height: Ogre's at
        // uv - d S (no overshoot), Babylon's at depth 1 - h at every angle.
        EXPECT_LT(glm::length(Vec2d(ogreFixed.uv[k]) - (uv0 - dir * (1 - h) * 0.04)), 1e-6) << k;
        EXPECT_LT(glm::length(Vec2d(bjsFixed.uv[k]) - (uv0 + below * 0.05)), 1e-6 + 1e-5 * tanTheta)
            << k;
        // PlayCanvas beta.20: 0.1 (h - 1/2) along the unit V.
        EXPECT_LT(glm::length(Vec2d(pcLimited.uv[k]) - (uv0 + dir * 0.1 * (h - 0.5))), 1e-6);
        const double samples = 15 + 11 * v.z, lowest = 1 - 14 / samples;
        if (std::fabs(lowest - h) > 1e-3) {
            const Vec2d want =
                lowest < h ? uv0 + below * 0.05 : uv0 - dir / v.z * 0.05 * (15 / samples);
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
    for (const Engine& e : engines()) {
        const GlslRun r = runPreset(e.preset, t, in);
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            if (std::string(e.preset) == "jme_steep" ||
                std::string(e.preset) == "babylon_occlusion") {
                EXPECT_FALSE(std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y)) << k;
                continue;
            }
            EXPECT_LT(glm::length(Vec2d(r.uv[k]) - Vec2d(in.uv0[k])), 1e-6) << e.preset << k;
        }
    }
}

// three.js's occlusion converges as its layers grow (below its 30-step cap: 29 layers reach
// the bottom), at a scale of -0.1 where its steps are several texels long.
TEST(Gl, ThreeJsOcclusionConvergesWithItsLayers) {
    Texture t = test::bricks(64);
    test::Fragments in = test::randomFragments(2000, 33, 60);
    double previous = INFINITY;
    const GlslRun fine = runPreset("threejs_occlusion", t, in,
                                   R"("parallax_min_layers":29,"parallax_max_layers":29,)"
                                   R"("parallax_scale":-0.1)");
    for (int layers : {4, 8, 24}) {
        const std::string n = std::to_string(layers);
        const GlslRun r = runPreset("threejs_occlusion", t, in,
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

// Each preset's shader against its C++ twin on 20,000 seeded fragments of the default brick
// map, views to 85 degrees: at least 99.5% within 1e-3 texel.
TEST(Gl, EnginePresetsMatchTheirCppTwins) {
    Texture bricks = test::bricks(128);
    test::Fragments in = test::randomFragments(20000, 34);
    for (const Engine& e : engines()) {
        const GlslRun gl = runPreset(e.preset, bricks, in);
        int over = 0;
        for (size_t k = 0; k < in.uv0.size(); ++k) {
            const Vec2f want = e.twin(bricks, in.uv0[k], in.view[k]);
            const double d = glm::length(Vec2d(gl.uv[k]) - Vec2d(want)) * 128;
            over += !(d <= 1e-3);
        }
        std::printf("%s: %d of 20000 over 1e-3 texel\n", e.preset, over);
        EXPECT_LE(over, 100) << e.preset;
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
        for (const Engine& e : engines()) {
            const GlslRun r = runPreset(e.preset, scene.height, in);
            int bad = 0;
            for (size_t k = 0; k < in.uv0.size(); ++k)
                bad += !(std::isfinite(r.uv[k].x) && std::isfinite(r.uv[k].y));
            EXPECT_EQ(bad, 0) << entry.path() << " " << e.preset;
        }
        ++scenes;
    }
    EXPECT_GE(scenes, 10);
}

}  // namespace
}  // namespace pgt
