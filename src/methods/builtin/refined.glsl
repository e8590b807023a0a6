// pgt built-ins "secant" and "contact" as GLSL (src/methods/builtin/refined.h): the secant method
// after a linear search (Risser, Shah, Pattanaik, JGT 2007) and contact-refinement parallax
// occlusion mapping (Riccardi 2018), on relief mapping's ray uv(t) = dp + ds * t with the
// depth d = 1 - h, generalised to any (s, b) as docs/model.md §6b.
// Uniforms: height_scale, height_bias (floats); linear_steps, secant_steps (secant) and
// layers (contact) as ints.
uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;
uniform int linear_steps;
uniform int secant_steps;
uniform int layers;

float pgtDepthAt(vec2 uv) { return 1.0 - pgt_sample(heightMap, uv).r; }

vec2 SecantRelief(vec2 uv0, vec3 V) {
    vec2 dp = uv0 + V.xy / V.z * (height_scale + height_bias);
    vec2 ds = -V.xy / V.z * height_scale;
    float size = 1.0 / float(linear_steps);
    float ta = 0.0;
    float fa = pgtDepthAt(dp);
    if (!(fa > 0.0)) return dp;
    float tb = ta, fb = fa;
    for (int i = 0; i < linear_steps; ++i) {
        tb = ta + size;
        fb = pgtDepthAt(dp + ds * tb) - tb;
        if (!(fb > 0.0)) break;
        ta = tb;
        fa = fb;
    }
    if (fb > 0.0) return dp + ds * tb;
    float t = tb;
    for (int i = 0; i < secant_steps; ++i) {
        t = ta + (tb - ta) * fa / (fa - fb);
        float f = pgtDepthAt(dp + ds * t) - t;
        if (f > 0.0) {
            ta = t;
            fa = f;
        } else {
            tb = t;
            fb = f;
        }
    }
    return dp + ds * t;
}

// The steep march from `uv` at `layer` while the layer is above the depth map.
void pgtMarch(inout vec2 uv, inout float layer, inout float depthValue, vec2 delta,
              float layerDepth) {
    for (int steps = 0; layer < depthValue; ++steps) {
        if (steps == 65536) break;
        uv -= delta;
        depthValue = pgtDepthAt(uv);
        layer += layerDepth;
    }
}

vec2 ContactRefinement(vec2 uv0, vec3 V) {
    float n = float(layers);
    float layerDepth = 1.0 / n;
    vec2 delta = V.xy / V.z * height_scale / n;
    vec2 uv = uv0 + V.xy / V.z * (height_scale + height_bias);
    float layer = 0.0;
    float depthValue = pgtDepthAt(uv);
    pgtMarch(uv, layer, depthValue, delta, layerDepth);
    if (layer > 0.0) {
        uv += delta;
        layer -= layerDepth;
        delta /= n;
        layerDepth /= n;
        depthValue = pgtDepthAt(uv);
        pgtMarch(uv, layer, depthValue, delta, layerDepth);
    }
    vec2 prev = uv + delta;
    float after = depthValue - layer;
    float before = pgtDepthAt(prev) - layer + layerDepth;
    float w = after / (after - before);
    return prev * w + uv * (1.0 - w);
}
