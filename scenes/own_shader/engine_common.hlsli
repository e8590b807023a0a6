// Typedefs and the height callback of engine_pom.hlsl, included as engines include theirs.
#ifndef ENGINE_COMMON_HLSLI
#define ENGINE_COMMON_HLSLI
typedef float real;
typedef float2 real2;
typedef float3 real3;

Texture2D _HeightMap;
SamplerState sampler_linear_clamp;

// The height callback: depth below the top of the relief, d = 1 - h.
real SampleDepth(real2 uv, real lod) {
    return 1.0 - _HeightMap.SampleLevel(sampler_linear_clamp, uv, lod).r;
}
#endif
