#version 330 core
// The fragment stage beside interface_block.vert: a depth map, offset parallax by V from the
// interpolated tangent-space positions, read through the fs_in block.
in VS_OUT {
    vec3 FragPos;
    vec2 TexCoords;
    vec3 TangentViewPos;
    vec3 TangentFragPos;
} fs_in;

out vec4 FragColor;

uniform sampler2D depthMap;
uniform float heightScale;

vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {
    float depth = texture(depthMap, texCoords).r;
    return texCoords - viewDir.xy / viewDir.z * (depth * heightScale);
}

void main() {
    vec3 viewDir = normalize(fs_in.TangentViewPos - fs_in.TangentFragPos);
    FragColor = vec4(ParallaxMapping(fs_in.TexCoords, viewDir), 0.0, 1.0);
}
