// pgt built-in "relief" as GLSL (src/methods/builtin/layered.h; Policarpo, Oliveira, Comba 2005's
// ray_intersect_rm: linear search over linear_steps - 1 depths, first crossing only, then
// binary_steps halvings), generalised to any (s, b) as docs/model.md §6b.
uniform sampler2D heightMap;
uniform float height_scale;
uniform float height_bias;
uniform int linear_steps;
uniform int binary_steps;

vec2 ReliefMapping(vec2 uv0, vec3 V) {
    vec2 dp = uv0 + V.xy / V.z * (height_scale + height_bias);
    vec2 ds = -V.xy / V.z * height_scale;
    float size = 1.0 / float(linear_steps);
    float depth = 0.0;
    float best = 1.0;
    for (int i = 0; i < linear_steps - 1; ++i) {
        depth += size;
        float t = 1.0 - pgt_sample(heightMap, dp + ds * depth).r;
        if (best > 0.996)
            if (depth >= t) best = depth;
    }
    depth = best;
    for (int i = 0; i < binary_steps; ++i) {
        size *= 0.5;
        float t = 1.0 - pgt_sample(heightMap, dp + ds * depth).r;
        if (depth >= t) {
            best = depth;
            depth -= 2.0 * size;
        }
        depth += size;
    }
    return dp + ds * best;
}
