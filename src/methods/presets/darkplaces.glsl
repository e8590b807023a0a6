// Engine preset: DarkPlaces' (Xonotic's) OffsetMapping() (shader_glsl.h lines 860-912; cvars in
// gl_rmain.c lines 172-179: r_glsl_offsetmapping_scale 0.04, _steps 2, _reliefmapping_steps 10,
// _reliefmapping_refinesteps 5; texture offsetscale 1, offsetbias 0; DarkPlacesEngine/darkplaces
// 2f25af65), re-implemented from its behaviour (docs/methods.md "Engine presets"). The height is
// the normal map's alpha (1 = top). Its eye vector is normalised in 3D and never divided by z;
// DarkPlaces' T points along -dP/dt, so its (-e.x, +e.y) is, in pgt's frame, the offset
// -scale normalize(V).xy: away from the eye, the relief below the polygon.
uniform sampler2D heightMap;
uniform float offset_scale;  // r_glsl_offsetmapping_scale x the texture's offsetscale: 0.04
uniform float offset_bias;   // the texture's offsetbias: 0
uniform int offset_steps;    // r_glsl_offsetmapping_steps 2 / _reliefmapping_steps 10
uniform int refine_steps;    // r_glsl_offsetmapping_reliefmapping_refinesteps 5

float dpHeight(vec2 uv) { return texture(heightMap, uv).r; }

vec2 dpOffset(vec3 V) { return -normalize(V).xy * offset_scale; }

// Offset mapping: N times tc += O / N ((1 - b) - h(tc)), h resampled at the moved tc.
vec2 DarkPlacesOffset(vec2 uv, vec3 V) {
    vec2 step = dpOffset(V) / float(offset_steps);
    vec2 tc = uv;
    for (int i = 0; i < offset_steps; ++i) tc += step * ((1.0 - offset_bias) - dpHeight(tc));
    return tc;
}

// Relief mapping: the ray (tc - O b, z = 1) along (O, -1) / N; N - 1 linear steps, each taken
// while the ray is at or above the height (step(h, z)), no break; then R refinements moving
// +-f/2 of a step by the same test, f = 1, 1/2, ...; the last move untested.
vec2 DarkPlacesRelief(vec2 uv, vec3 V) {
    vec3 O = vec3(dpOffset(V), -1.0);
    vec3 RT = vec3(uv - O.xy * offset_bias, 1.0);
    O /= float(offset_steps);
    for (int i = 1; i < offset_steps; ++i) RT += O * step(dpHeight(RT.xy), RT.z);
    float f = 1.0;
    for (int i = 0; i < refine_steps; ++i) {
        RT += O * (f * step(dpHeight(RT.xy), RT.z) - 0.5 * f);
        f *= 0.5;
    }
    return RT.xy;
}
