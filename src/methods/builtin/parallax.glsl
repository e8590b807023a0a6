// pgt built-in "parallax" as GLSL (src/methods/builtin/simple.h; Welsh 2004 §4.1's ARB program:
// MAD h*s+b; RCP V.z; MUL; MAD offset*V.xy + T0), written op for op like the C++.
// Uniforms: height_scale = s, height_bias = b (UV units), e.g. bound to the case's:
// "uniforms": {"height_scale": "scale", "height_bias": "bias"}.
uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;

vec2 ParallaxMapping(vec2 uv, vec3 V) {
    float height = pgt_sample(heightMap, uv).r * height_scale + height_bias;
    float rcpZ = 1.0 / V.z;
    height = height * rcpZ;
    return height * V.xy + uv;
}
