// Engine preset: O3DE Atom's parallax (Gems/Atom/Feature/Common/Assets/ShaderLib/Atom/Features/
// ParallaxMapping.azsli: BasicParallaxMapping lines 131-146, AdvancedParallaxMapping lines
// 161-345, the quality's step counts lines 357-371; Materials/Types/MaterialInputs/
// ParallaxPropertyGroup.json: factor 0.05, offset 0, algorithm POM, quality Low (16 steps);
// o3de/o3de 354a2acc), re-implemented from its behaviour (docs/methods.md "Engine presets").
// The depth is 1 - h (heightmap white = top); V is the unit tangent-space direction to the
// eye, no y flip. The step count does not follow the view angle.
uniform sampler2D heightMap;
uniform float factor;  // "Height Map Scale", 0.05
uniform int steps;     // quality: Low 16, Medium 32, High 64, Ultra 128

float o3deDepth(vec2 uv) { return 1.0 - texture(heightMap, uv).r; }

// Basic: one fetch, -V.xy d factor (no division by V.z).
vec2 O3deBasic(vec2 uv, vec3 V) {
    vec3 v = normalize(V);
    return uv - v.xy * o3deDepth(uv) * factor;
}

// The march of Steep, POM, Relief and Contact: P(t) = -V / V.z (t factor) from t = 0, steps
// of 1/N, while the depth is below the ray (s > t); no iteration cap in O3DE (pgt's runaway
// guard only).
struct O3deMarch {
    vec3 P, delta;
    float t, step, s, prev;
};
O3deMarch o3deMarch(vec2 uv, vec3 V) {
    vec3 v = normalize(V);
    O3deMarch m;
    m.step = 1.0 / float(steps);
    m.t = 0.0;
    m.delta = -v * factor / v.z * m.step;
    m.P = vec3(0.0);
    m.s = o3deDepth(uv + m.P.xy);
    m.prev = m.s;
    int guard = 0;
    while (m.s > m.t && guard < 65536) {
        m.t += m.step;
        m.P += m.delta;
        m.prev = m.s;
        m.s = o3deDepth(uv + m.P.xy);
        ++guard;
    }
    return m;
}

// A result above the polygon (P.z > 0) is dropped whole.
vec2 o3deResult(vec2 uv, vec3 P) { return P.z > 0.0 ? uv : uv + P.xy; }

vec2 O3deSteep(vec2 uv, vec3 V) { return o3deResult(uv, o3deMarch(uv, V).P); }

// POM: between the last two points by their depth differences (only when the march moved).
vec2 O3dePom(vec2 uv, vec3 V) {
    O3deMarch m = o3deMarch(uv, V);
    if (m.t > 0.0) {
        float prevDiff = m.prev - (m.t - m.step);
        float curDiff = m.t - m.s;
        m.P = mix(m.P - m.delta, m.P, prevDiff / (prevDiff + curDiff));
    }
    return o3deResult(uv, m.P);
}

// Relief: N halvings, each moving by the sign of (depth - t) (0: no move), then resampling.
vec2 O3deRelief(vec2 uv, vec3 V) {
    O3deMarch m = o3deMarch(uv, V);
    if (m.t > 0.0) {
        for (int i = 0; i < steps; ++i) {
            m.delta *= 0.5;
            m.step *= 0.5;
            float sigma = sign(m.s - m.t);
            m.P += sigma * m.delta;
            m.t += sigma * m.step;
            m.s = o3deDepth(uv + m.P.xy);
        }
    }
    return o3deResult(uv, m.P);
}

// Contact refinement: one step back, then the march again at 1/N of the step; no interpolation.
vec2 O3deContact(vec2 uv, vec3 V) {
    O3deMarch m = o3deMarch(uv, V);
    if (m.t > 0.0) {
        m.P -= m.delta;
        m.t -= m.step;
        m.s = m.prev;
        vec3 delta = m.delta * m.step;
        float step = m.step * m.step;
        int guard = 0;
        while (m.s > m.t && guard < 65536) {
            m.t += step;
            m.P += delta;
            m.s = o3deDepth(uv + m.P.xy);
            ++guard;
        }
    }
    return o3deResult(uv, m.P);
}
