#version 450
// A Vulkan-style vertex stage written for pgt's tests in the manner of public parallax
// samples: it moves the eye and the vertex into the vertex's tangent space and hands both to
// the fragment stage. `handedness` 0 builds the bitangent as cross(N, T) and ignores the
// tangent's w, as such samples ship; 1 multiplies by w, as a mirrored mesh needs.
layout(location = 0) in vec3 inPos;
layout(location = 1) in vec2 inUV;
layout(location = 2) in vec3 inNormal;
layout(location = 3) in vec4 inTangent;

layout(set = 0, binding = 0) uniform Matrices {
    mat4 projection;
    mat4 view;
    mat4 model;
    vec4 cameraPos;
} ubo;

layout(push_constant) uniform Options {
    float handedness;
} options;

layout(location = 0) out vec2 outUV;
layout(location = 1) out vec3 outTangentViewPos;
layout(location = 2) out vec3 outTangentFragPos;

out gl_PerVertex {
    vec4 gl_Position;
};

void main() {
    vec3 worldPos = vec3(ubo.model * vec4(inPos, 1.0));
    mat3 normalToWorld = mat3(ubo.model);
    vec3 N = normalize(normalToWorld * inNormal);
    vec3 T = normalize(normalToWorld * inTangent.xyz);
    vec3 B = cross(N, T) * mix(1.0, inTangent.w, options.handedness);
    mat3 worldToTangent = transpose(mat3(T, B, N));
    outTangentViewPos = worldToTangent * ubo.cameraPos.xyz;
    outTangentFragPos = worldToTangent * worldPos;
    outUV = inUV;
    gl_Position = ubo.projection * ubo.view * vec4(worldPos, 1.0);
}
