// pgt's pom (docs/model.md §6b) as HLSL: a Texture2D and a SamplerState, globals set by name.
// tests/own_shader_test.cpp holds it to the built-in pom through HLSL -> SPIR-V -> GLSL.
Texture2D heightMap;
SamplerState heightSampler;
float height_scale;
float height_bias;
float min_layers;
float max_layers;

float depthAt(float2 uv) { return 1.0 - heightMap.SampleLevel(heightSampler, uv, 0.0).r; }

float2 ParallaxOcclusion(float2 uv0, float3 V) {
    float a = abs(V.z);
    float numLayers = max_layers * (1.0 - a) + min_layers * a;
    float layerDepth = 1.0 / numLayers;
    float2 delta = V.xy / V.z * height_scale / numLayers;
    float2 uv = uv0 + V.xy / V.z * (height_scale + height_bias);
    float depth = depthAt(uv);
    float layer = 0.0;
    [loop] while (layer < depth) {
        uv -= delta;
        depth = depthAt(uv);
        layer += layerDepth;
    }
    float2 prev = uv + delta;
    float after = depth - layer;
    float before = depthAt(prev) - layer + layerDepth;
    float w = after / (after - before);
    return lerp(uv, prev, w);
}
