// pgt built-ins "steep" and "pom" as GLSL (src/methods/builtin/layered.h; LearnOpenGL's steep
// parallax and parallax occlusion listings generalised to any (s, b) as docs/model.md §6b pins
// them down): the march starts where the eye ray enters the top of the relief, layers
// mix(max, min, |V.z|), depth d = 1 - h read from the height map.
// Uniforms: height_scale, height_bias, min_layers, max_layers (floats), max_steps (int,
// 0 = unbounded up to pgt's safety cap of 65536).
uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;
uniform float min_layers;
uniform float max_layers;
uniform int max_steps;

float pgtDepth(vec2 uv) { return 1.0 - pgt_sample(heightMap, uv).r; }

// The steep march; returns the last layer's texcoords, its depth value and layer depth.
vec2 pgtSteep(vec2 uv0, vec3 V, out vec2 delta, out float depthValue, out float layer,
              out float layerDepth) {
    float a = abs(V.z);
    float numLayers = max_layers * (1.0 - a) + min_layers * a;  // GLSL mix, spelt out
    layerDepth = 1.0 / numLayers;
    layer = 0.0;
    vec2 P = V.xy / V.z * height_scale;
    delta = P / numLayers;
    vec2 uv = uv0 + V.xy / V.z * (height_scale + height_bias);
    depthValue = pgtDepth(uv);
    int limit = max_steps > 0 ? max_steps : 65536;
    int steps = 0;
    while (layer < depthValue) {
        if (steps == limit) break;
        uv -= delta;
        depthValue = pgtDepth(uv);
        layer += layerDepth;
        ++steps;
    }
    return uv;
}

vec2 SteepParallax(vec2 uv0, vec3 V) {
    vec2 delta;
    float depthValue, layer, layerDepth;
    return pgtSteep(uv0, V, delta, depthValue, layer, layerDepth);
}

vec2 ParallaxOcclusion(vec2 uv0, vec3 V) {
    vec2 delta;
    float depthValue, layer, layerDepth;
    vec2 uv = pgtSteep(uv0, V, delta, depthValue, layer, layerDepth);
    vec2 prev = uv + delta;
    float after = depthValue - layer;
    float before = pgtDepth(prev) - layer + layerDepth;
    float w = after / (after - before);
    return prev * w + uv * (1.0 - w);
}
