// Engine preset: Unity HDRP Lit, pixel displacement (parallax occlusion mapping), written
// anew from Unity-Technologies/Graphics: LitDataDisplacement.hlsl (ApplyPerPixelDisplacement,
// UV0 mapping) and the core library's PerPixelDisplacement.hlsl (ParallaxOcclusionMapping).
// docs/methods.md "Engine presets" lists what is reproduced and what is not.
// - Heights: 1 is the top (the polygon), 0 the bottom; the relief is always pushed inwards
//   by `height_amplitude` UV units (pgt: s = A, b = -A). Defaults: _HeightPoMAmplitude 2 cm
//   is _HeightAmplitude 0.02, on a primitive of 1 m (_PPDPrimitiveLength/Width 1, so
//   _InvPrimScale 1) with tiling 1: A = 0.02 UV.
// - Step count: the view vector in UV space, normalize(V.xy * A, V.z); its angle from the
//   normal through Unity's FastACosPos polynomial, over pi/2 and saturated, mixes
//   _PPDMinSamples (5) and _PPDMaxSamples (15); the float truncates to int; at most 256.
// - A linear search from the top: a first step before the loop, then until a sample's
//   height exceeds the ray's; then up to 3 secant steps between the bracketing heights, which
//   stop early when |ray - height| <= 0.01; uv' = uv + the last secant offset.
// Not reproduced: the LOD fade (pgt samples level 0, so lod = 0 and nothing fades),
// triplanar and planar mappings, tiling or object scale other than 1, the depth offset.
// Unity's V points to the eye with v up, as pgt's does.
uniform sampler2D heightMap;
uniform float height_amplitude;  // UV units; 0.02 by default
uniform float ppd_min_samples;   // 5
uniform float ppd_max_samples;   // 15

// Unity's FastACosPos: acos on [0, 1] by a quadratic times sqrt(1 - x).
float unityFastAcosPos(float x) {
    x = abs(x);
    return ((0.0468878 * x - 0.203471) * x + 1.570796) * sqrt(1.0 - x);
}

float unityHeight(vec2 uv) { return textureLod(heightMap, uv, 0.0).r; }

vec2 UnityHdrpPom(vec2 uv, vec3 V) {
    vec3 viewUV = normalize(vec3(V.xy * height_amplitude, V.z));
    float unitAngle = clamp(unityFastAcosPos(viewUV.z) * (2.0 / 3.14159265358979), 0.0, 1.0);
    int numSteps = min(int(mix(ppd_min_samples, ppd_max_samples, unitAngle)), 256);
    float stepSize = 1.0 / float(numSteps);
    vec2 perStep = stepSize * (viewUV.xy / -viewUV.z);

    vec2 offsetNow = vec2(0.0);
    float prevHeight = unityHeight(uv + offsetNow);
    offsetNow += perStep;
    float currHeight = unityHeight(uv + offsetNow);
    float rayHeight = 1.0 - stepSize;
    for (int i = 0; i < numSteps; ++i) {
        if (currHeight > rayHeight) break;
        prevHeight = currHeight;
        rayHeight -= stepSize;
        offsetNow += perStep;
        currHeight = unityHeight(uv + offsetNow);
    }

    float top = rayHeight + stepSize, bottom = rayHeight;  // the ray at the bracket's ends
    float gapTop = top - prevHeight, gapBottom = bottom - currHeight;
    vec2 offset = offsetNow;
    for (int i = 0; i < 3; ++i) {
        float hit = (top * gapBottom - bottom * gapTop) / (gapBottom - gapTop);
        offset = (1.0 - hit) * perStep * float(numSteps);
        float gap = hit - unityHeight(uv + offset);
        if (abs(gap) <= 0.01) break;
        if (gap < 0.0) {
            gapBottom = gap;
            bottom = hit;
        } else {
            gapTop = gap;
            top = hit;
        }
    }
    return uv + offset;
}
