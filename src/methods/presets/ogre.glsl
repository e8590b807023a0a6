// Engine preset: Ogre's RTShader System normal-map parallax (Media/RTShaderLib/SGXLib_NormalMap.glsl
// SGX_Generate_Parallax_Texcoord, lines 55-125; Components/RTShaderSystem/src/
// OgreShaderExNormalMapLighting.cpp: height scale 0.04 (line 49), POM_LAYER_COUNT 32 (line 68);
// OGRECave/ogre 3e955a16 = v14.5.2 + 186), re-implemented from its behaviour (docs/methods.md
// "Engine presets"). The depth is 1 - the normal map's alpha (pgt: 1 - h). Ogre negates its
// eye vector's y for meshes, whose v runs down the image (Direct3D's convention): in pgt's
// convention (v up) that flip is already folded in, so V is used as it is.
uniform sampler2D heightMap;
uniform float height_scale;  // 0.04
uniform int layer_count;     // POM_LAYER_COUNT, 32

float ogreDepth(vec2 uv) { return 1.0 - texture(heightMap, uv).r; }

// normalmap_space parallax: one fetch, uv - V.xy / V.z d s.
vec2 OgreParallax(vec2 uv, vec3 V) {
    vec3 e = normalize(V);
    return uv - e.xy / e.z * ogreDepth(uv) * height_scale;
}

// normalmap_space parallax_occlusion: the whole shift S = V.xy s WITHOUT division by V.z, in
// layer_count steps; each step moves first, then compares the previous layer's depth (i L,
// strict) with the depth there, and only then takes the layer's depth: the coordinate runs one
// step ahead (a constant one-layer overshoot, kept). The interpolation runs whether or not the
// loop found the surface.
vec2 OgreOcclusion(vec2 uv, vec3 V) {
    vec3 e = normalize(V);
    float L = 1.0 / float(layer_count);
    vec2 delta = e.xy * height_scale / float(layer_count);
    vec2 current = uv;
    float depth = 0.0, layer = 0.0;
    for (int i = 0; i < layer_count; ++i) {
        current = uv - float(i + 1) * delta;
        depth = ogreDepth(current);
        if (float(i) * L > depth) break;
        layer = float(i + 1) * L;
    }
    vec2 prev = current + delta;
    float after = depth - layer;
    float before = ogreDepth(prev) - layer + L;
    float w = after / (after - before);
    return mix(current, prev, w);
}

// pgt's variant beside OgreOcclusion: each step compares its own layer's depth (i + 1) L with
// the depth where it moved, so the coordinate and the layer stay together (no one-layer
// overshoot); everything else (no division by V.z, 32 layers) as Ogre ships it.
vec2 OgreOcclusionFixed(vec2 uv, vec3 V) {
    vec3 e = normalize(V);
    float L = 1.0 / float(layer_count);
    vec2 delta = e.xy * height_scale / float(layer_count);
    vec2 current = uv;
    float depth = ogreDepth(uv), layer = 0.0;
    for (int i = 0; i < layer_count && layer < depth; ++i) {
        current = uv - float(i + 1) * delta;
        depth = ogreDepth(current);
        layer = float(i + 1) * L;
    }
    if (layer == 0.0) return uv;
    vec2 prev = current + delta;
    float after = depth - layer;
    float before = ogreDepth(prev) - layer + L;
    float w = after / (after - before);
    return mix(current, prev, w);
}
