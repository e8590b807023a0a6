// pgt built-ins "iterative" (Lengyel FGED 2 Listing 7.9) and "tangent_plane" (Lengyel FGED 2 Eq. 7.50) as GLSL
// (src/methods/builtin/lengyel.h), on Lengyel FGED 2's derived maps: normalMap = unit normal m (RGB),
// parallaxMap = m_z * (s*h + b) in UV units, built by pgt for the case's (s, b)
// ("normal_sampler": "normalMap", "parallax_sampler": "parallaxMap").
uniform sampler2D normalMap;
uniform sampler2D parallaxMap;
uniform int iterations;

vec2 IterativeParallax(vec2 uv0, vec3 V) {
    vec2 pdir = V.xy / float(iterations);
    vec2 uv = uv0;
    for (int i = 0; i < iterations; ++i) {
        float parallax = pgt_sample(parallaxMap, uv).r;
        uv += pdir * parallax;
    }
    return uv;
}

vec2 TangentPlaneParallax(vec2 uv0, vec3 V) {
    vec3 n = normalize(pgt_sample(normalMap, uv0).xyz);
    float parallax = pgt_sample(parallaxMap, uv0).r;
    float ndotv = dot(n, V);
    return uv0 + V.xy * parallax / ndotv;
}
