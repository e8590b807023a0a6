// Engine preset: Babylon.js's parallax (Shaders/ShadersInclude/bumpFragmentFunctions.fx:
// parallaxOcclusion lines 15-66, parallaxOffset lines 68-78, the sample constants lines 10-12;
// bumpFragment.fx; @babylonjs/core 9.31.0: parallaxScaleBias 0.05, the height in the bump
// texture's alpha, 1 = at the polygon), re-implemented from its behaviour (docs/methods.md
// "Engine presets"). With the default mesh frame and PARALLAX_RHS set from the scene's
// handedness, the offset goes toward the eye by scale h |V.xy| (a bump above the polygon) and
// the occlusion march away from it (a depth below); Babylon's textures load with v up
// (invertY), as pgt's. V is Babylon's tangent-space vector, level 1: the transpose of its
// frame times the unit eye direction, used as it is (unit in the mesh tangents' frame, where
// pgt's per-pixel V stands for it; of another length in the cotangent frame, cotangent_frame.glsl).
#include "cotangent_frame.glsl"
uniform sampler2D heightMap;
uniform float parallax_scale;  // parallaxScaleBias, 0.05 (no bias is ever added)

float babylonHeight(vec2 uv) { return texture(heightMap, uv).r; }

// parallaxOffset: scale h V.xy, no division by V.z, h at the unshifted uv.
vec2 BabylonOffset(vec2 uv, vec3 V) {
    return uv + parallax_scale * babylonHeight(uv) * V.xy;
}

// parallaxOcclusion: the whole march maxOff = -normalize(V.xy) scale |V.xy| / V.z, away from the
// eye (Babylon's eye-to-surface vector and its frame's sign, net; head-on normalize(vec2(0)) is
// not a number, kept); a float sample count 15 + dot(-V, N) (4 - 15) =
// 15 + 11 cos(theta) (more samples head-on than at grazing, the reverse of its comment); a loop
// of exactly 15 passes, each sampling; the first height above the ray stops the search with the
// linear crossing; no hit: 15 steps' offset, no interpolation.
vec2 BabylonOcclusion(vec2 uv, vec3 V) {
    vec3 v = V;
    vec2 maxOff = -normalize(v.xy) * (parallax_scale * length(v.xy) / v.z);
    float samples = 15.0 + dot(-v, vec3(0.0, 0.0, 1.0)) * (4.0 - 15.0);
    float stepSize = 1.0 / samples;
    float ray = 1.0, prevHeight = 1.0;
    vec2 curOff = vec2(0.0), prevOff = vec2(0.0);
    bool searching = true;
    for (int i = 0; i < 15; ++i) {
        float h = babylonHeight(uv + curOff);
        if (searching) {
            if (h > ray) {
                float d1 = h - ray;
                float d2 = (ray + stepSize) - prevHeight;
                float r = d1 / (d1 + d2);
                curOff = r * prevOff + (1.0 - r) * curOff;
                searching = false;
            } else {
                ray -= stepSize;
                prevOff = curOff;
                curOff += stepSize * maxOff;
                prevHeight = h;
            }
        }
    }
    return uv + curOff;
}

// pgt's variant beside BabylonOcclusion, what its comment intends: mix(15, 4, cos(theta))
// samples (15 at grazing, 4 head-on), a loop as long as the count, and no offset head-on
// instead of normalize(vec2(0))'s not-a-number.
vec2 BabylonOcclusionFixed(vec2 uv, vec3 V) {
    vec3 v = normalize(V);
    if (v.x == 0.0 && v.y == 0.0) return uv;
    vec2 maxOff = -v.xy / v.z * parallax_scale;
    float samples = mix(15.0, 4.0, v.z);
    int passes = int(ceil(samples));
    float stepSize = 1.0 / samples;
    float ray = 1.0, prevHeight = 1.0;
    vec2 curOff = vec2(0.0), prevOff = vec2(0.0);
    for (int i = 0; i <= passes; ++i) {
        float h = babylonHeight(uv + curOff);
        if (h > ray) {
            float d1 = h - ray;
            float d2 = (ray + stepSize) - prevHeight;
            float r = d1 / (d1 + d2);
            return uv + r * prevOff + (1.0 - r) * curOff;
        }
        ray -= stepSize;
        prevOff = curOff;
        curOff += stepSize * maxOff;
        prevHeight = h;
    }
    return uv + curOff;
}
