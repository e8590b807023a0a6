// Engine preset: three.js r131's examples/jsm/shaders/ParallaxShader.js (npm three@0.131.0,
// lines 60-177) at the defaults of its example webgl_materials_parallaxmap.html (mode relief,
// scale 0.005 passed negated, layers 20-25), re-implemented from its behaviour (docs/methods.md
// "Engine presets"). three.js builds V from screen derivatives (perturbUv): V.xy is the eye
// direction's tangential part in UV units (the unit eye vector's tangent-space xy divided by
// the world length of one UV unit), V.z = dot(N, E); so V = (V.x / l, V.y / l, V.z) in pgt's
// terms, l = world_per_uv. The bump map's value is treated as a depth (bright = deep) and
// the march goes toward the eye for the example's negative scale (the last crossing along the
// ray, not the first: kept).
uniform sampler2D heightMap;
uniform float parallax_scale;   // the example: -0.005
uniform float parallax_min_layers;  // 20
uniform float parallax_max_layers;  // 25
uniform float world_per_uv;     // l of the base (1 on the default plane)

float threeDepth(vec2 uv) { return texture(heightMap, uv).r; }

#ifdef PGT_ENGINE_INPUTS
vec3 threeView(vec3 V) { return V; }  // the engine path hands three.js's own vector
#else
vec3 threeView(vec3 V) { return vec3(V.xy / world_per_uv, V.z); }
#endif

#ifdef PGT_ENGINE_INPUTS
// What three.js itself hands parallaxMap (the preset's engine path, "inputs": "engine"):
// perturbUv's projection of the unit eye direction e. The two screen derivatives of the
// position span the tangent plane; e's part in it, solved in that basis, moves uv by the two
// uv derivatives: xy = (grad u . e, grad v . e) in UV units, z = N . e; threeView passes it on
// as it is (world_per_uv is not read).
vec3 threeEngineV(vec2 uv) {
    vec3 p = pgt_world_position;
    vec3 n = normalize(pgt_world_normal);
    vec3 e = normalize(pgt_camera_position - p);
    vec3 sigmaX = dFdx(p);
    vec3 sigmaY = dFdy(p);
    vec3 r1 = cross(sigmaY, n);
    vec3 r2 = cross(n, sigmaX);
    float det = dot(sigmaX, r1);
    vec2 screen = vec2(dot(r1, e), dot(r2, e)) / det;
    vec2 tex = dFdx(uv) * screen.x + dFdy(uv) * screen.y;
    return vec3(tex, dot(n, e));
}
#endif

// parallaxMap, basic mode: no division by V.z.
vec2 ThreeBasic(vec2 uv, vec3 V) {
    vec3 v = threeView(V);
    return uv - v.xy * threeDepth(uv) * parallax_scale;
}

// The shared march: layers mix(max, min, |V.z|) as a float; at most 30 steps, the test first
// (stop when the depth is at or below the layer).
struct ThreeMarch {
    vec2 uv, step;
    float depth, layer, layerHeight;
};
ThreeMarch threeMarch(vec2 uv, vec3 V) {
    vec3 v = threeView(V);
    ThreeMarch m;
    float layers = mix(parallax_max_layers, parallax_min_layers, abs(v.z));
    m.layerHeight = 1.0 / layers;
    m.layer = 0.0;
    m.step = parallax_scale * v.xy / v.z / layers;
    m.uv = uv;
    m.depth = threeDepth(m.uv);
    for (int i = 0; i < 30; i += 1) {
        if (m.depth <= m.layer) break;
        m.layer += m.layerHeight;
        m.uv -= m.step;
        m.depth = threeDepth(m.uv);
    }
    return m;
}

vec2 ThreeSteep(vec2 uv, vec3 V) { return threeMarch(uv, V).uv; }

// Occlusion: the interpolation between the last two layers (no guard on a zero denominator).
vec2 ThreeOcclusion(vec2 uv, vec3 V) {
    ThreeMarch m = threeMarch(uv, V);
    vec2 prev = m.uv + m.step;
    float next = m.depth - m.layer;
    float before = threeDepth(prev) - m.layer + m.layerHeight;
    float w = next / (next - before);
    return w * prev + (1.0 - w) * m.uv;
}

// Relief: half a layer back, then 5 halvings (halve, sample, step by the strict test).
vec2 ThreeRelief(vec2 uv, vec3 V) {
    ThreeMarch m = threeMarch(uv, V);
    vec2 d = m.step * 0.5;
    float dl = m.layerHeight * 0.5;
    vec2 c = m.uv + d;
    float layer = m.layer - dl;
    for (int i = 0; i < 5; i += 1) {
        d *= 0.5;
        dl *= 0.5;
        float depth = threeDepth(c);
        if (depth > layer) {
            c -= d;
            layer += dl;
        } else {
            c += d;
            layer -= dl;
        }
    }
    return c;
}
