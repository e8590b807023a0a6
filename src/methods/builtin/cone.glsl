// pgt built-in "cone" as GLSL (src/methods/builtin/cone.h; Dummer, "Cone Step Mapping", 2006): cone
// steps on pgt's conservative cone map for the bilinear surface, then bisections.
// Samplers: heightMap (bilinear) and coneMap (the ratio per cell as pgt uploads it: R32F,
// cellsX x cellsY, read with texelFetch). pgt sets pgt_cone_cells, pgt_cone_top (the map's
// highest e), pgt_cone_inverted (the map is built for e = -h, s < 0), pgt_map_size and
// pgt_map_repeat. Uniforms: height_scale, height_bias (floats), steps, refine_steps (ints).
uniform sampler2D heightMap;
uniform sampler2D coneMap;
uniform float height_scale;
uniform float height_bias;
uniform int steps;
uniform int refine_steps;
uniform ivec2 pgt_cone_cells;
uniform float pgt_cone_top;
uniform int pgt_cone_inverted;
uniform ivec2 pgt_map_size;
uniform int pgt_map_repeat;

// floor(x) wrapped into [0, n) (repeat) or clamped to it (heightfield/cone_map.h coneIndex).
int coneIndex(float x, int n) {
    int i = int(clamp(floor(x), -1.0e9, 1.0e9));
    if (pgt_map_repeat != 0) {
        i = i % n;
        if (i < 0) i += n;
        return i;
    }
    return clamp(i, 0, n - 1);
}

// The cone map's cell holding uv: lattice x = u W - 0.5.
float coneRatio(vec2 uv) {
    ivec2 c = ivec2(coneIndex(uv.x * float(pgt_map_size.x) - 0.5, pgt_cone_cells.x),
                    coneIndex(uv.y * float(pgt_map_size.y) - 0.5, pgt_cone_cells.y));
    return texelFetch(coneMap, c, 0).r;
}

// The eye ray over heights e (e = h, or -h for s < 0): uv(e) = uv0 + dir (a e + b); r is the
// UV it travels per unit of e.
struct ConeRay {
    vec2 uv0, dir;
    float sgn, a, b, r;
};

ConeRay coneRay(vec2 uv0, vec3 V) {
    vec2 dir = V.xy / V.z;
    float a = abs(height_scale);
    return ConeRay(uv0, dir, pgt_cone_inverted != 0 ? -1.0 : 1.0, a, height_bias,
                   a * sqrt(dir.x * dir.x + dir.y * dir.y));
}

vec2 coneAt(ConeRay ray, float e) { return ray.uv0 + ray.dir * (ray.a * e + ray.b); }

vec2 ConeStep(vec2 uv0, vec3 V) {
    if (!(V.z > 0.0)) return vec2(0.0 / 0.0);
    ConeRay ray = coneRay(uv0, V);
    float sgn = ray.sgn, r = ray.r;
    float e = pgt_cone_top;
    vec2 uv = coneAt(ray, e);
    for (int i = 0; i < steps; ++i) {
        float gap = e - sgn * pgt_sample(heightMap, uv).r;
        if (!(gap > 0.0)) break;
        float ratio = coneRatio(uv);
        e -= ratio * gap / (ratio + r);
        uv = coneAt(ray, e);
    }
    if (refine_steps == 0) return uv;
    float gap = e - sgn * pgt_sample(heightMap, uv).r;
    if (!(gap > 0.0)) return uv;
    float above = e, below = e - gap;
    for (int i = 0; i < refine_steps; ++i) {
        float mid = (above + below) * 0.5;
        if (mid - sgn * pgt_sample(heightMap, coneAt(ray, mid)).r > 0.0)
            above = mid;
        else
            below = mid;
    }
    float e1 = (above + below) * 0.5;
    return coneAt(ray, e1);
}

// pgt built-in "relaxed_cone" (src/methods/builtin/cone.h; Policarpo & Oliveira, GPU Gems 3 ch. 18):
// relaxed cone steps with the gap saturated at 0, then halvings over the way travelled.
// Sampler relaxedConeMap: the relaxed ratios, one per texel (R32F, width x height, nearest).
// Uniforms: height_scale, height_bias, cone_steps, binary_steps.
uniform sampler2D relaxedConeMap;
uniform int cone_steps;
uniform int binary_steps;

vec2 RelaxedConeStep(vec2 uv0, vec3 V) {
    if (!(V.z > 0.0)) return vec2(0.0 / 0.0);
    ConeRay ray = coneRay(uv0, V);
    float sgn = ray.sgn, r = ray.r;
    float top = pgt_cone_top;
    float e = top;
    for (int i = 0; i < cone_steps; ++i) {
        vec2 uv = coneAt(ray, e);
        float gap = max(e - sgn * pgt_sample(heightMap, uv).r, 0.0);
        ivec2 c = ivec2(coneIndex(uv.x * float(pgt_map_size.x), pgt_map_size.x),
                        coneIndex(uv.y * float(pgt_map_size.y), pgt_map_size.y));
        float ratio = texelFetch(relaxedConeMap, c, 0).r;
        e -= ratio * gap / (ratio + r);
    }
    float half_ = (top - e) * 0.5;
    float mid = top - half_;
    for (int i = 0; i < binary_steps; ++i) {
        half_ *= 0.5;
        if (mid - sgn * pgt_sample(heightMap, coneAt(ray, mid)).r > 0.0)
            mid -= half_;
        else
            mid += half_;
    }
    return coneAt(ray, mid);
}
