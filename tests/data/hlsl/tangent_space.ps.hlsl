// The pixel stage beside tangent_space.vs.hlsl, the twin of glsl/tangent_space.frag: offset
// parallax with V from the tangent-space positions the vertex stage interpolated, read from
// the stage's input struct as a pixel shader's main reads them.
Texture2D heightMap : register(t1);
SamplerState heightSampler : register(s1);

struct Params {
    float heightScale;
    float heightBias;
};
[[vk::push_constant]] Params params;

struct VSOutput {
    float4 Pos : SV_POSITION;
    [[vk::location(0)]] float2 UV : TEXCOORD0;
    [[vk::location(1)]] float3 TangentViewPos : TEXCOORD1;
    [[vk::location(2)]] float3 TangentFragPos : TEXCOORD2;
};

float2 offsetParallax(float2 uv, float3 V) {
    float h = heightMap.Sample(heightSampler, uv).r * params.heightScale + params.heightBias;
    return uv + h * V.xy / V.z;
}

float4 main(VSOutput input) : SV_TARGET {
    float3 V = normalize(input.TangentViewPos - input.TangentFragPos);
    return float4(offsetParallax(input.UV, V), 0.0, 1.0);
}
