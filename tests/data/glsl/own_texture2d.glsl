#version 330 core
// Desktop GLSL 3.30 that defines a function of its own named texture2D (a name the legacy
// dialects reserve): it compiles because pgt maps the legacy names only for 100, 110, 120.
uniform sampler2D depthMap;
uniform float height_scale;

vec4 texture2D(sampler2D s, vec2 uv) { return texture(s, uv); }

vec2 ParallaxMapping(vec2 uv, vec3 V) {
    return uv - V.xy * (1.0 - texture2D(depthMap, uv).r) * height_scale;
}
