// Engine preset: jMonkeyEngine 3's Common/ShaderLib/Parallax.glsllib (read at
// jMonkeyEngine/jmonkeyengine 7277b5d8, lines 2-76; the material defaults in
// Common/MatDefs/Light/Lighting.j3md and PBRLighting.j3md: ParallaxHeight 0.05, SteepParallax
// off), re-implemented from its behaviour (docs/methods.md "Engine presets"). Heights are read
// as they are (1 = top, the ParallaxMap's red channel); V is the tangent-space direction to
// the eye, y not flipped (jME's textures load with v up, as pgt's).
uniform sampler2D heightMap;
uniform float parallax_height;  // ParallaxHeight, default 0.05

float jmeHeight(vec2 uv) { return texture(heightMap, uv).r; }

#ifdef PGT_ENGINE_INPUTS
// PBRLighting.frag's V (jme_tangents): the interpolated tangent normalised but not made
// orthogonal to the normal, B = w cross(N, T), and the direction to the eye in that frame.
vec3 jmePbrV() {
    vec3 n = normalize(pgt_world_normal);
    vec3 t = normalize(pgt_world_tangent.xyz);
    vec3 b = pgt_world_tangent.w * cross(n, t);
    vec3 e = normalize(pgt_camera_position - pgt_world_position);
    return vec3(dot(e, t), dot(e, b), dot(e, n));
}
#endif

// The default ("classic"): one fetch at uv, the offset s (h - 0.6) cos(theta) along the unit
// V's xy: multiplied by V.z where parallax divides, zero at h = 0.6.
vec2 JmeParallax(vec2 uv, vec3 V) {
    vec3 n = normalize(V);
    float h = jmeHeight(uv);
    float d = (h * parallax_height - 0.6 * parallax_height) * n.z;
    return uv + d * n.xy;
}

// SteepParallax: the ray from height 1 at uv down to height 0 at uv - P, P = normalize(V.xy)
// tan(theta) 0.3 s; a float count mix(6, 1000 * 0.3 s, 1 - cos(theta)) of samples, the
// coordinate moved before the first compare; exit on the first sample above the ray; the
// line through the last two samples meets the ray (the first step's previous height is 0, not
// 1: jME's quirk, kept). Head-on, normalize(vec2(0)) is not a number: so is uv'.
vec2 JmeSteepParallax(vec2 uv, vec3 V) {
    float tanTheta = sqrt(dot(V, V) - V.z * V.z) / V.z;
    float scale = 0.3 * parallax_height;
    vec2 P = normalize(V.xy) * tanTheta * scale;
    float samples = mix(6.0, 1000.0 * scale, 1.0 - normalize(V).z);
    float delta = 1.0 / samples;
    float current = 0.0, previous = 0.0, bound = 1.0;
    vec2 c = uv;
    for (float k = 0.0; k < samples && current <= bound; k += 1.0) {
        c -= delta * P;
        previous = current;
        current = jmeHeight(c);
        bound -= delta;
    }
    float d2 = (bound + delta) - previous;
    float d1 = bound - current;
    float amount = (bound * d2 - (bound + delta) * d1) / (d2 - d1);
    return uv - P * (1.0 - amount);
}

// pgt's variant beside JmeSteepParallax: head-on (V.xy = 0) there is no offset, instead of
// normalize(vec2(0))'s not-a-number; everything else as jME ships it.
vec2 JmeSteepParallaxFixed(vec2 uv, vec3 V) {
    if (V.x == 0.0 && V.y == 0.0) return uv;
    return JmeSteepParallax(uv, V);
}
