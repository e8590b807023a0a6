#version 450
// A fragment shader in the style of Vulkan samples (pgt's own, tests/own_shader_test.cpp):
// set and binding layouts, a uniform block and a push-constant block with instance names,
// stage inputs and an output with locations, an array texture, the height as depth in the
// alpha of a normal map. pgt's pom (docs/model.md §6b) as a function of it.
#extension GL_ARB_separate_shader_objects : enable
#extension GL_ARB_shading_language_420pack : enable

layout (set = 0, binding = 1) uniform sampler2D sColorMap;
layout (set = 0, binding = 2) uniform sampler2D sNormalHeightMap;
layout (set = 1, binding = 0) uniform sampler2DArray sDetail;

layout (std140, set = 0, binding = 0) uniform UBO
{
    float heightScale;
    float parallaxBias;
    float maxLayers;
} ubo;

layout (push_constant) uniform PushConsts {
    float minLayers;
} pc;

layout (location = 0) in vec2 inUV;
layout (location = 1) flat in vec3 inTangentViewPos;
layout (location = 2) in vec3 inTangentFragPos;

layout (location = 0) out vec4 outFragColor;

float depthAt(vec2 uv) { return texture(sNormalHeightMap, uv).a; }

vec2 parallaxOcclusion(vec2 uv, vec3 V)
{
    uv = uv + V.xy / V.z * (ubo.heightScale + ubo.parallaxBias);
    float numLayers = mix(ubo.maxLayers, pc.minLayers, abs(V.z));
    vec2 delta = V.xy / V.z * ubo.heightScale / numLayers;
    float depth = depthAt(uv), layer = 0.0;
    while (layer < depth) {
        uv -= delta;
        depth = depthAt(uv);
        layer += 1.0 / numLayers;
    }
    vec2 prev = uv + delta;
    float after = depth - layer, before = depthAt(prev) - layer + 1.0 / numLayers;
    return mix(uv, prev, after / (after - before));
}

void main()
{
    vec3 V = normalize(inTangentViewPos - inTangentFragPos);
    vec2 uv = parallaxOcclusion(inUV, V);
    outFragColor = texture(sColorMap, uv) + 0.0 * texture(sDetail, vec3(uv, 1.0));
}
