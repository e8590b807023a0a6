#version 330
// pgt's pom (docs/model.md §6b) split over files as engines split theirs: the march's helpers
// come from pom_steps.glsl through #include (twice: its #pragma once keeps one copy), and the
// height is in the texture's G channel (a scene says "texture": "height.g"). Saved with a
// UTF-8 byte-order mark and CRLF line ends. tests/own_shader_test.cpp holds it to pom.
#include "pom_steps.glsl"
#include "pom_steps.glsl"

uniform float height_scale;
uniform float height_bias;

vec2 ParallaxOcclusion(vec2 uv0, vec3 V) {
    float a = abs(V.z);
    float numLayers = layerCount(a);
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
    return mix(uv, prev, after / (after - before));
}
