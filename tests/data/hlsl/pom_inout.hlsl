// pgt's pom (docs/model.md §6b) as an engine's function: its texture and sampler are
// parameters (the sampler defaulting to a global), its answer goes back through an inout
// float4 (both UV sets moved), an enum picks the march's end, the helpers come from an
// include with #pragma once. It has no return value: a scene calls it through "body".
// tests/own_shader_test.cpp holds it to the built-in pom.
#include "pom_march.hlsli"
#include "pom_march.hlsli"

SamplerState linear_wrap;

void ParallaxOcclusion_Impl(inout float4 uvsets, float3 V, float scale, float bias,
                            float minLayers, float maxLayers, Texture2D map,
                            uint end = (uint)MarchEnd::Interpolated,
                            SamplerState state = linear_wrap) {
    float a = abs(V.z);
    float numLayers = maxLayers * (1.0 - a) + minLayers * a;
    float layerDepth = 1.0 / numLayers;
    float2 delta = V.xy / V.z * scale / numLayers;
    float2 start = uvsets.xy;
    float2 uv = start + V.xy / V.z * (scale + bias) * Positive;
    float depth = depthAt(map, state, uv);
    float layer = 0.0;
    [loop] while (layer < depth) {
        uv -= delta;
        depth = depthAt(map, state, uv);
        layer += layerDepth;
    }
    if (end == (uint)MarchEnd::Interpolated) {
        float2 prev = uv + delta;
        float after = depth - layer;
        float before = depthAt(map, state, prev) - layer + layerDepth;
        uv = lerp(uv, prev, after / (after - before));
    }
    uvsets += (uv - start).xyxy;
}
