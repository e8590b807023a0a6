#version 100
// Parallax occlusion mapping as WebGL 1 code is written (GLSL ES 1.00): precision
// statements, the lod extension's texture2DLodEXT, a loop with a constant bound left by
// break. It computes pgt's pom (docs/model.md §6b: depth d = 1 - h, layers mixed by |V.z|,
// the march starting where the eye ray enters the top of the relief), so that
// tests/gl_test.cpp can hold it to the built-in: the dialect test of docs/methods.md.
#extension GL_EXT_shader_texture_lod : enable
precision highp float;
precision highp int;

uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;
uniform float min_layers;
uniform float max_layers;

float depthAt(vec2 uv) {
    return 1.0 - texture2DLodEXT(heightMap, uv, 0.0).r;
}

vec2 ParallaxOcclusionES(vec2 uv0, vec3 V) {
    float a = abs(V.z);
    float numLayers = max_layers * (1.0 - a) + min_layers * a;
    float layerDepth = 1.0 / numLayers;
    vec2 P = V.xy / V.z * height_scale;
    vec2 delta = P / numLayers;
    vec2 uv = uv0 + V.xy / V.z * (height_scale + height_bias);
    float depth = depthAt(uv);
    float layer = 0.0;
    for (int i = 0; i < 65536; i++) {
        if (!(layer < depth)) break;
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
