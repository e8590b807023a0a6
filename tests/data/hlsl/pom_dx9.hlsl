// pgt's pom (docs/model.md §6b) in DirectX 9 / Cg style: one sampler2D global read with
// tex2Dlod, parameters as globals; saved with a UTF-8 byte-order mark and CRLF line ends, as
// Windows editors save it. tests/own_shader_test.cpp holds it to the built-in pom.
sampler2D heightMap;
float height_scale;
float height_bias;
float min_layers;
float max_layers;

float depthAt(float2 uv) { return 1.0 - tex2Dlod(heightMap, float4(uv, 0.0, 0.0)).r; }

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
    return lerp(uv, prev, after / (after - before));
}
