// Preset: parallax occlusion mapping as in N. Tatarchuk, "Dynamic Parallax Occlusion Mapping
// with Approximate Soft Shadows", I3D 2006, and its DirectX SDK sample
// (ParallaxOcclusionMapping.fx, RenderScenePS), written anew. docs/methods.md "Engine presets" lists
// what is reproduced and what is not.
// - Heights: 1 is the top (the polygon); the parallax offset vector is V.xy / V.z times
//   g_fHeightMapScale (the sample's default texture, "stones", sets 0.02): pgt s = 0.02,
//   b = -0.02. The sample writes it normalize(V.xy) * |V.xy| / V.z, undefined where
//   V.xy = 0; here it is V.xy / V.z, equal everywhere else.
// - Steps: (int) lerp(g_nMaxSamples 50, g_nMinSamples 8, dot(V, N)).
// - The march: each step first moves the offset and lowers the bound by 1/steps, then
//   samples; the first sample above the bound gives pt1 = (bound, height) and pt2 = (bound +
//   step, previous height, 1 before the first sample); the amount is (pt1.x * D2 - pt2.x *
//   D1) / (D2 - D1) with D = x - height (0 where the denominator is 0), uv' = uv - offset *
//   (1 - amount). No sample above the bound leaves pt1 = pt2 = 0: amount 0.
// - Samples: tex2Dgrad with the original texcoord's ddx/ddy (textureGrad with dFdx/dFdy of
//   uv0: level 0 unless the scene's map has mipmaps; in screen layout, as in the sample).
// Not reproduced: the mip-level LOD switch to bump mapping (the sample's threshold of 3),
// the soft shadows.
uniform sampler2D heightMap;
uniform float height_map_scale;  // 0.02
uniform float min_samples;       // 8
uniform float max_samples;       // 50

vec2 TatarchukPom(vec2 uv, vec3 V) {
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    vec2 parallaxOffset = V.xy / V.z * height_map_scale;
    int numSteps = int(mix(max_samples, min_samples, V.z));
    float stepSize = 1.0 / float(numSteps);
    vec2 perStep = stepSize * parallaxOffset;
    vec2 current = uv;
    float bound = 1.0, prevHeight = 1.0;
    vec2 pt1 = vec2(0.0), pt2 = vec2(0.0);
    for (int i = 0; i < numSteps; ++i) {
        current -= perStep;
        float height = textureGrad(heightMap, current, dx, dy).r;
        bound -= stepSize;
        if (height > bound) {
            pt1 = vec2(bound, height);
            pt2 = vec2(bound + stepSize, prevHeight);
            break;
        }
        prevHeight = height;
    }
    float d2 = pt2.x - pt2.y, d1 = pt1.x - pt1.y;
    float denominator = d2 - d1;
    float amount = denominator == 0.0 ? 0.0 : (pt1.x * d2 - pt2.x * d1) / denominator;
    return uv - parallaxOffset * (1.0 - amount);
}
