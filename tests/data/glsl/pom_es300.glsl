#version 300 es
// Parallax occlusion mapping as WebGL 2 code is written (GLSL ES 3.00): precision
// qualifiers on the sampler, textureLod, a while loop. pgt's pom (docs/model.md §6b), held
// to the built-in by tests/gl_test.cpp: the dialect test of docs/methods.md.
precision highp float;

uniform highp sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;
uniform float min_layers;
uniform float max_layers;

float depthAt(vec2 uv) { return 1.0 - textureLod(heightMap, uv, 0.0).r; }

vec2 ParallaxOcclusionES(vec2 uv0, vec3 V) {
    float a = abs(V.z);
    float numLayers = max_layers * (1.0 - a) + min_layers * a;
    float layerDepth = 1.0 / numLayers;
    vec2 delta = V.xy / V.z * height_scale / numLayers;
    vec2 uv = uv0 + V.xy / V.z * (height_scale + height_bias);
    float depth = depthAt(uv);
    float layer = 0.0;
    while (layer < depth) {
        uv -= delta;
        depth = depthAt(uv);
        layer += layerDepth;
    }
    vec2 prev = uv + delta;
    float after = depth - layer;
    float before = depthAt(prev) - layer + layerDepth;
    float w = after / (after - before);
    return prev * w + uv * (1.0 - w);
}
