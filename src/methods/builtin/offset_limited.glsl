// pgt built-in "offset_limited" as GLSL (src/methods/builtin/simple.h; Welsh 2004 §4.3: no division by V.z).
uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;

vec2 OffsetLimited(vec2 uv, vec3 V) {
    float height = pgt_sample(heightMap, uv).r * height_scale + height_bias;
    return height * V.xy + uv;
}
