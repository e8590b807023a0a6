// Engine preset: PlayCanvas's standard material parallax (src/scene/shader-lib chunk
// standard/frag/parallax, read at playcanvas/engine fcadbb3b = v2.22.0-beta.19, lines 5-12, and
// at 59ffaff5 = v2.22.0-beta.20; standard-material.js: heightMapFactor 1, the uniform factor x
// 0.025 until beta.19, x 0.1 from beta.20), re-implemented from its behaviour (docs/methods.md
// "Engine presets"). The height is read as is (1 = top) and remapped around mid-grey,
// h' = h s - s / 2. PlayCanvas's tangent frame has its y axis along decreasing v, so its view
// vector's y is minus pgt's V.y.
#include "cotangent_frame.glsl"
uniform sampler2D heightMap;
uniform float height_map_factor;  // heightMapFactor, default 1

float playcanvasHeight(vec2 uv, float s) { return texture(heightMap, uv).r * s - s * 0.5; }

// Every release from 2016 to v2.22.0-beta.19: s = 0.025 factor, the offset h' V.xy / (V.z +
// 0.42) in PlayCanvas's frame, whose y is pgt's -V.y: the v offset points away from the eye
// (the defect the beta.20 commit names, kept).
vec2 PlayCanvasParallax(vec2 uv, vec3 V) {
    float h = playcanvasHeight(uv, 0.025 * height_map_factor);
    vec3 v = vec3(V.x, -V.y, V.z);
    v.z += 0.42;
    return uv + h * v.xy / v.z;
}

// The same with the v offset's sign corrected (pgt's variant, not an engine's).
vec2 PlayCanvasParallaxFixed(vec2 uv, vec3 V) {
    float h = playcanvasHeight(uv, 0.025 * height_map_factor);
    vec3 v = V;
    v.z += 0.42;
    return uv + h * v.xy / v.z;
}

// v2.22.0-beta.20: s = 0.1 factor, offset limiting h' (V.x, V.y) of the normalised V, its y
// negated in PlayCanvas's frame (so along pgt's +V.y).
vec2 PlayCanvasOffsetLimited(vec2 uv, vec3 V) {
    float h = playcanvasHeight(uv, 0.1 * height_map_factor);
    vec3 v = normalize(V);
    return uv + h * v.xy;
}
