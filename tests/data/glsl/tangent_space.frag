#version 450
// The fragment stage beside tangent_space.vert: offset parallax with V from the tangent-space
// positions the vertex stage interpolated.
layout(set = 0, binding = 1) uniform sampler2D heightMap;

layout(location = 0) in vec2 inUV;
layout(location = 1) in vec3 inTangentViewPos;
layout(location = 2) in vec3 inTangentFragPos;

layout(location = 0) out vec4 outColor;

layout(push_constant) uniform Params {
    float heightScale;
    float heightBias;
} params;

vec2 offsetParallax(vec2 uv, vec3 V) {
    float h = texture(heightMap, uv).r * params.heightScale + params.heightBias;
    return uv + h * V.xy / V.z;
}

void main() {
    vec3 V = normalize(inTangentViewPos - inTangentFragPos);
    outColor = vec4(offsetParallax(inUV, V), 0.0, 1.0);
}
