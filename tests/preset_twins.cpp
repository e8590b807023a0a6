// The GLSL presets written again in C++ (methods/presets/preset_twins.h): float, each shader's
// order of operations, its shipped uniforms.
#include "preset_twins.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "methods/method.h"
#include "methods/presets/presets.h"

namespace pgt {

namespace {

// The shaders' texture(heightMap, uv).r: the bilinear height.
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

// DarkPlaces: O = -scale normalize(V).xy; offset mapping N times tc += O / N (1 - b - h(tc));
// relief the ray (O, -1) / N from (uv - O b, 1), N - 1 steps while z >= h, then R refinements
// of +-f/2.
Vec2f darkplacesTwin(const Texture& t, Vec2f uv, Vec3f V, bool relief, float scale, float bias,
                     int n, int r) {
    const Vec3f e = glm::normalize(V);
    const Vec2f O = -Vec2f(e.x, e.y) * scale;
    if (!relief) {
        Vec2f tc = uv;
        for (int i = 0; i < n; ++i) tc += O / float(n) * ((1.0f - bias) - height(t, tc));
        return tc;
    }
    Vec3f step(O, -1.0f), RT(uv - O * bias, 1.0f);
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

// Babylon: offset uv + s h V.xy; occlusion away from the eye, 15 + 11 cos(theta) samples
// as a float, 15 passes, the linear crossing at the first height above the ray.
Vec2f babylonTwin(const Texture& t, Vec2f uv, Vec3f V, bool occlusion, float s) {
    const Vec3f v = glm::normalize(V);
    if (!occlusion) return uv + s * height(t, uv) * Vec2f(v.x, v.y);
    const Vec2f maxOff =
        -glm::normalize(Vec2f(v.x, v.y)) * (s * glm::length(Vec2f(v.x, v.y)) / v.z);
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

Vec2f babylonFixedTwin(const Texture& t, Vec2f uv, Vec3f V, float s) {
    const Vec3f v = glm::normalize(V);
    if (v.x == 0 && v.y == 0) return uv;
    const Vec2f maxOff = -Vec2f(v.x, v.y) / v.z * s;
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

// Unity HDRP's POM with its FastACosPos step count and secant refinement; Tatarchuk's march.
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

// Godot 4: depth 1 - h; the default offsets along V.xy without dividing by V.z; deep parallax
// marches from the base UV by V.xy s / layers, then interpolates the last two layers.
float godotDepth(const Texture& t, Vec2f uv) { return 1.0f - height(t, uv); }

Vec2f godotTwin(const Texture& t, Vec2f uv, Vec3f V, float scale) {
    const float depth = godotDepth(t, uv);
    return uv - Vec2f(V.x, V.y) * depth * scale * 0.01f;
}

Vec2f godotDeepTwin(const Texture& t, Vec2f uv, Vec3f V, float scale, float lo, float hi) {
    const float layers = glslMix(hi, lo, std::fabs(V.z));
    const float layerDepth = 1.0f / layers;
    const Vec2f delta = Vec2f(V.x, V.y) * scale * 0.01f / layers;
    Vec2f ofs = uv;
    float depth = godotDepth(t, ofs), current = 0.0f;
    for (int guard = 0; current < depth && guard < 65536; ++guard) {
        ofs -= delta;
        depth = godotDepth(t, ofs);
        current += layerDepth;
    }
    const Vec2f prev = ofs + delta;
    const float after = depth - current;
    const float before = godotDepth(t, prev) - current + layerDepth;
    const float w = after / (after - before);
    return ofs * (1.0f - w) + prev * w;
}

// Bevy: a depth texture (1 - h); layers mix(max, 1, |V.z|) (not clamped), steps
// s / layers (-V.xy) / |V.z|, at most layers + 1 of them; then the occlusion interpolation or
// `steps` halvings (Relief).
float bevyDepth(const Texture& t, Vec2f uv) { return 1.0f - height(t, uv); }

struct BevyMarch {
    Vec2f uv, delta;
    float layerDepth, current, depth;
};

BevyMarch bevyMarch(const Texture& t, Vec2f uv, Vec3f V, float scale, float maxLayers) {
    BevyMarch m;
    const float steepness = std::fabs(V.z);
    const float layers = glslMix(maxLayers, 1.0f, steepness);
    m.layerDepth = 1.0f / layers;
    m.delta = scale * m.layerDepth * (-Vec2f(V.x, V.y)) / steepness;
    m.current = 0.0f;
    m.depth = bevyDepth(t, uv);
    for (int i = 0; m.depth > m.current && i <= int(layers); i++) {
        m.current += m.layerDepth;
        uv += m.delta;
        m.depth = bevyDepth(t, uv);
    }
    m.uv = uv;
    return m;
}

Vec2f bevyOcclusionTwin(const Texture& t, Vec2f uv0, Vec3f V, float scale, float maxLayers) {
    BevyMarch m = bevyMarch(t, uv0, V, scale, maxLayers);
    const Vec2f prev = m.uv - m.delta;
    const float next = m.depth - m.current;
    const float before = bevyDepth(t, prev) - m.current + m.layerDepth;
    const float w = next / (next - before);
    return m.uv * (1.0f - w) + prev * w;
}

Vec2f bevyReliefTwin(const Texture& t, Vec2f uv0, Vec3f V, float scale, float maxLayers,
                     int steps) {
    BevyMarch m = bevyMarch(t, uv0, V, scale, maxLayers);
    Vec2f delta = m.delta * 0.5f, uv = m.uv - delta;
    float deltaDepth = 0.5f * m.layerDepth, current = m.current - deltaDepth;
    for (int i = 0; i < steps; i++) {
        const float depth = bevyDepth(t, uv);
        delta *= 0.5f;
        deltaDepth *= 0.5f;
        if (depth > current)
            uv += delta, current += deltaDepth;
        else
            uv -= delta, current -= deltaDepth;
    }
    return uv;
}

// A preset's uniforms as its entry in methods/presets/presets.cpp sets them: the twins read
// their values from there, so a default is written once.
struct Uniforms {
    std::map<std::string, double> values;
    float operator()(const std::string& name) const {
        const auto it = values.find(name);
        if (it == values.end()) throw std::logic_error("preset twin: no uniform " + name);
        return float(it->second);
    }
    int integer(const std::string& name) const { return int((*this)(name)); }
};

struct TwinOf {
    std::function<Vec2f(const Texture&, Vec2f, Vec3f, const Uniforms&)> run;
    bool nanHeadOn = false;
};

TwinOf o3de(O3de mode) {
    return {[mode](const Texture& t, Vec2f uv, Vec3f v, const Uniforms& u) {
        return o3deTwin(t, uv, v, mode, u("factor"), mode == O3de::Basic ? 16 : u.integer("steps"));
    }};
}

TwinOf three(Three mode) {
    return {[mode](const Texture& t, Vec2f uv, Vec3f v, const Uniforms& u) {
        const bool layers = mode != Three::Basic;
        return threeTwin(t, uv, v, mode, u("parallax_scale"),
                         layers ? u("parallax_min_layers") : 20.0f,
                         layers ? u("parallax_max_layers") : 25.0f);
    }};
}

// Every GLSL preset's twin, reading its shipped uniforms (methods/presets/presets.cpp).
// PlayCanvas scales its heightMapFactor by 0.025 to beta.19 and by 0.1 from beta.20 (in the
// shader, not a uniform).
std::map<std::string, TwinOf> makeTwins() {
    using T = const Texture&;
    using U = const Uniforms&;
    return {
        {"jme",
         {[](T t, Vec2f uv, Vec3f v, U u) { return jmeTwin(t, uv, v, u("parallax_height")); }}},
        // normalize(vec2(0)) head-on: no finite uv' (the shipped shader's quirk)
        {"jme_steep",
         {[](T t, Vec2f uv, Vec3f v, U u) { return jmeSteepTwin(t, uv, v, u("parallax_height")); },
          true}},
        {"jme_steep_fixed", {[](T t, Vec2f uv, Vec3f v, U u) {
             return jmeSteepFixedTwin(t, uv, v, u("parallax_height"));
         }}},
        {"playcanvas", {[](T t, Vec2f uv, Vec3f v, U u) {
             return playcanvasTwin(t, uv, v, 0.025f * u("height_map_factor"), -1.0f, false);
         }}},
        {"playcanvas_fixed", {[](T t, Vec2f uv, Vec3f v, U u) {
             return playcanvasTwin(t, uv, v, 0.025f * u("height_map_factor"), 1.0f, false);
         }}},
        {"playcanvas_offset_limited", {[](T t, Vec2f uv, Vec3f v, U u) {
             return playcanvasTwin(t, uv, v, 0.1f * u("height_map_factor"), 1.0f, true);
         }}},
        {"ogre_parallax", {[](T t, Vec2f uv, Vec3f v, U u) {
             return ogreTwin(t, uv, v, u("height_scale"), 32, false);
         }}},
        {"ogre_pom", {[](T t, Vec2f uv, Vec3f v, U u) {
             return ogreTwin(t, uv, v, u("height_scale"), u.integer("layer_count"), true);
         }}},
        {"ogre_pom_fixed", {[](T t, Vec2f uv, Vec3f v, U u) {
             return ogreFixedTwin(t, uv, v, u("height_scale"), u.integer("layer_count"));
         }}},
        {"o3de_pom", o3de(O3de::Pom)},
        {"o3de_steep", o3de(O3de::Steep)},
        {"o3de_relief", o3de(O3de::Relief)},
        {"o3de_contact", o3de(O3de::Contact)},
        {"o3de_basic", o3de(O3de::Basic)},
        {"darkplaces_offset", {[](T t, Vec2f uv, Vec3f v, U u) {
             return darkplacesTwin(t, uv, v, false, u("offset_scale"), u("offset_bias"),
                                   u.integer("offset_steps"), 0);
         }}},
        {"darkplaces_relief", {[](T t, Vec2f uv, Vec3f v, U u) {
             return darkplacesTwin(t, uv, v, true, u("offset_scale"), u("offset_bias"),
                                   u.integer("offset_steps"), u.integer("refine_steps"));
         }}},
        {"babylon_offset", {[](T t, Vec2f uv, Vec3f v, U u) {
             return babylonTwin(t, uv, v, false, u("parallax_scale"));
         }}},
        // normalize(vec2(0)) head-on as well
        {"babylon_occlusion",
         {[](T t, Vec2f uv, Vec3f v, U u) {
              return babylonTwin(t, uv, v, true, u("parallax_scale"));
          },
          true}},
        {"babylon_occlusion_fixed", {[](T t, Vec2f uv, Vec3f v, U u) {
             return babylonFixedTwin(t, uv, v, u("parallax_scale"));
         }}},
        {"threejs_basic", three(Three::Basic)},
        {"threejs_steep", three(Three::Steep)},
        {"threejs_occlusion", three(Three::Occlusion)},
        {"threejs_relief", three(Three::Relief)},
        {"godot",
         {[](T t, Vec2f uv, Vec3f v, U u) { return godotTwin(t, uv, v, u("heightmap_scale")); }}},
        {"godot_deep", {[](T t, Vec2f uv, Vec3f v, U u) {
             return godotDeepTwin(t, uv, v, u("heightmap_scale"), u("heightmap_min_layers"),
                                  u("heightmap_max_layers"));
         }}},
        {"bevy_occlusion", {[](T t, Vec2f uv, Vec3f v, U u) {
             return bevyOcclusionTwin(t, uv, v, u("depth_scale"), u("max_layer_count"));
         }}},
        {"bevy_relief", {[](T t, Vec2f uv, Vec3f v, U u) {
             return bevyReliefTwin(t, uv, v, u("depth_scale"), u("max_layer_count"),
                                   u.integer("max_steps"));
         }}},
        {"unity_hdrp", {[](T t, Vec2f uv, Vec3f v, U u) {
             return unityTwin(t, uv, v, u("height_amplitude"), u("ppd_min_samples"),
                              u("ppd_max_samples"));
         }}},
        {"tatarchuk", {[](T t, Vec2f uv, Vec3f v, U u) {
             return tatarchukTwin(t, uv, v, u("height_map_scale"), u("min_samples"),
                                  u("max_samples"));
         }}},
    };
}

}  // namespace

const PresetTwin* presetTwin(const std::string& preset) {
    // Each GLSL preset's twin bound to that preset's own uniforms. NAME_tangents runs NAME's
    // function on the base frame's per-pixel V, with the signs its engine's tangent path hands
    // it (MethodPreset::tangentsSignX/Y): NAME's twin on that V, which is a twin of NAME itself
    // only where NAME is fed V too (tests/gl_engines_test.cpp).
    static const std::map<std::string, PresetTwin> twins = [] {
        const std::map<std::string, TwinOf> of = makeTwins();
        const std::string suffix = "_tangents";
        std::map<std::string, PresetTwin> out;
        for (const MethodPreset& p : methodPresets()) {
            const bool tangents =
                p.name.size() > suffix.size() &&
                p.name.compare(p.name.size() - suffix.size(), suffix.size(), suffix) == 0;
            auto it = of.find(tangents ? p.name.substr(0, p.name.size() - suffix.size()) : p.name);
            if (it == of.end()) continue;
            Uniforms u;
            for (const GlslSpec::Uniform& un : p.glsl.uniforms)
                if (!un.values.empty()) u.values[un.name] = un.values[0];
            const float sx = tangents ? float(p.tangentsSignX) : 1.0f,
                        sy = tangents ? float(p.tangentsSignY) : 1.0f;
            out[p.name] = {[run = it->second.run, u, sx, sy](const Texture& t, Vec2f uv, Vec3f v) {
                               return run(t, uv, Vec3f(sx * v.x, sy * v.y, v.z), u);
                           },
                           it->second.nanHeadOn};
        }
        return out;
    }();
    auto it = twins.find(preset);
    return it == twins.end() ? nullptr : &it->second;
}

}  // namespace pgt
