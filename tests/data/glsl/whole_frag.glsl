// A whole fragment shader of a GL 2 engine (no #version: GLSL 1.10): varyings, a main() that
// writes gl_FragColor, and the parallax as statements inside main() (pgt's pom, docs/model.md
// §6b). A scene runs those statements through "body"; pgt compiles the file with its main()
// renamed. tests/own_shader_test.cpp holds it to the built-in pom.
varying vec2 vTexCoord;
varying vec3 vViewTangent;

uniform sampler2D uHeightMap;
uniform sampler2D uDiffuseMap;
uniform float uHeightScale;
uniform float uHeightBias;

float depthAt(vec2 uv) { return 1.0 - texture2DLod(uHeightMap, uv, 0.0).r; }

void main() {
    vec3 V = normalize(vViewTangent);
    vec2 uv = vTexCoord + V.xy / V.z * (uHeightScale + uHeightBias);
    float numLayers = mix(32.0, 8.0, abs(V.z));
    vec2 delta = V.xy / V.z * uHeightScale / numLayers;
    float depth = depthAt(uv), layer = 0.0;
    while (layer < depth) {
        uv -= delta;
        depth = depthAt(uv);
        layer += 1.0 / numLayers;
    }
    vec2 prev = uv + delta;
    float after = depth - layer, before = depthAt(prev) - layer + 1.0 / numLayers;
    uv = mix(uv, prev, after / (after - before));
    gl_FragColor = texture2D(uDiffuseMap, uv);
}
