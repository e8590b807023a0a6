// A vertex stage in HLSL written for pgt's tests, the twin of glsl/tangent_space.vert in the
// manner of Vulkan samples compiled from HLSL: input and output structs with semantics, the
// matrices in a cbuffer and applied as mul(M, v), the bitangent built as cross(N, T) times a
// `handedness` blend of 1 (as such samples ship: w ignored) and the tangent's w.
struct VSInput {
    [[vk::location(0)]] float3 Pos : POSITION0;
    [[vk::location(1)]] float2 UV : TEXCOORD0;
    [[vk::location(2)]] float3 Normal : NORMAL0;
    [[vk::location(3)]] float4 Tangent : TANGENT0;
};

struct UBO {
    float4x4 projection;
    float4x4 view;
    float4x4 model;
    float4 cameraPos;
};
cbuffer ubo : register(b0) { UBO ubo; }

struct Options {
    float handedness;
};
[[vk::push_constant]] Options options;

struct VSOutput {
    float4 Pos : SV_POSITION;
    [[vk::location(0)]] float2 UV : TEXCOORD0;
    [[vk::location(1)]] float3 TangentViewPos : TEXCOORD1;
    [[vk::location(2)]] float3 TangentFragPos : TEXCOORD2;
};

VSOutput main(VSInput input) {
    VSOutput output = (VSOutput)0;
    float3 worldPos = mul(ubo.model, float4(input.Pos, 1.0)).xyz;
    float3 N = normalize(mul((float3x3)ubo.model, input.Normal));
    float3 T = normalize(mul((float3x3)ubo.model, input.Tangent.xyz));
    float3 B = cross(N, T) * lerp(1.0, input.Tangent.w, options.handedness);
    // Rows T, B, N: mul(TBN, x) is x in the vertex's tangent space.
    float3x3 TBN = float3x3(T, B, N);
    output.TangentViewPos = mul(TBN, ubo.cameraPos.xyz);
    output.TangentFragPos = mul(TBN, worldPos);
    output.UV = input.UV;
    output.Pos = mul(ubo.projection, mul(ubo.view, float4(worldPos, 1.0)));
    return output;
}
