#version 100
// Parallax occlusion in WebGL 1 style with the height in the alpha of a normal map (pgt's
// "normal+height" layout), the sampler a global the function expects the engine to declare
// (pgt declares it), an offset returned and the view vector from the eye to the surface
// unless LEFT_HANDED_VIEW is defined. The layers are pgt's pom's (docs/model.md §6b), so
// that tests/own_shader_test.cpp holds it to the built-in through a scene's "call".
#extension GL_EXT_shader_texture_lod : enable
precision highp float;

uniform float uMinLayers;
uniform float uMaxLayers;

float depthOf(vec2 uv) { return 1.0 - texture2DLodEXT(bumpSampler, uv, 0.0).a; }

vec2 occlusionOffset(vec3 eyeToSurface, vec3 normal, vec2 uv0, float scale, float bias) {
#ifdef LEFT_HANDED_VIEW
    vec3 V = eyeToSurface;
#else
    vec3 V = -eyeToSurface;
#endif
    float a = abs(dot(V, normal));
    float numLayers = mix(uMaxLayers, uMinLayers, a);
    float layerDepth = 1.0 / numLayers;
    vec2 delta = V.xy / V.z * scale / numLayers;
    vec2 uv = uv0 + V.xy / V.z * (scale + bias);
    float depth = depthOf(uv);
    float layer = 0.0;
    for (int i = 0; i < 65536; i++) {
        if (!(layer < depth)) break;
        uv -= delta;
        depth = depthOf(uv);
        layer += layerDepth;
    }
    vec2 prev = uv + delta;
    float after = depth - layer;
    float before = depthOf(prev) - layer + layerDepth;
    float w = after / (after - before);
    return mix(uv, prev, w) - uv0;
}
