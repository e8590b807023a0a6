// pgt built-in "iterative_slope" (src/methods/builtin/slope.h; Premecz 2006, iterative parallax
// mapping with slope information) as GLSL, written op for op like the C++: the eye ray's point
// (uv, z) starts on the polygon and moves `iterations` times along V by (s h + b - z) n.z, h and
// the normal n (Lengyel FGED 2's derived map, "normal_sampler": "normalMap") read at its uv.
// Uniforms: height_scale = s, height_bias = b (UV units), iterations.
uniform sampler2D heightMap;
uniform sampler2D normalMap;
uniform float height_scale;
uniform float height_bias;
uniform int iterations;

vec2 IterativeSlopeParallax(vec2 uv0, vec3 V) {
    vec2 uv = uv0;
    float z = 0.0;
    for (int i = 0; i < iterations; ++i) {
        vec3 n = pgt_sample(normalMap, uv).xyz;
        float h = pgt_sample(heightMap, uv).r;
        float step = (h * height_scale + height_bias - z) * n.z;
        uv += V.xy * step;
        z += V.z * step;
    }
    return uv;
}
