// The layered ray marches: steep parallax (LearnOpenGL "Steep Parallax Mapping", the
// deferred-renderer blog's ParallaxMapping), parallax occlusion mapping (steep + the interpolation
// tail of LearnOpenGL/the deferred-renderer blog, the parallax-mapping encyclopedia article's POM),
// and relief mapping's linear + binary search (Policarpo, Oliveira, Comba 2005), generalised to any
// (s, b) as docs/model.md §6b pins them down.
#pragma once

#include <cmath>

#include "methods/method.h"

namespace pgt {

// Where the march starts: the eye ray's entry into the top of the relief (h = 1, height
// s + b); = uv0 exactly at the documents' native b = -s, since s + b is then exactly 0.
template <class Real>
inline Vec2<Real> reliefTopEntry(Vec2<Real> uv0, Vec3<Real> v, Real s, Real b) {
    return uv0 + Vec2<Real>(v.x, v.y) / v.z * (s + b);
}

// State of a finished steep march, shared by steep and pom.
template <class Real>
struct SteepMarch {
    Vec2<Real> uv;     // currentTexCoords
    Vec2<Real> delta;  // deltaTexCoords
    Real depthValue;   // currentDepthMapValue
    Real layer;        // currentLayerDepth
    Real layerDepth;   // 1 / numLayers
};

// LearnOpenGL steep listing: numLayers = mix(maxLayers, minLayers, |V.z|) (the deferred-renderer
// blog takes abs, LearnOpenGL max(.,0)); P = V.xy / V.z * height_scale; deltaTexCoords = P /
// numLayers; march while currentLayerDepth < currentDepthMapValue. max_steps bounds it as the
// deferred-renderer blog's for-loop does.
template <class Real>
SteepMarch<Real> steepMarch(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                            const LayerParameters& cfg) {
    SteepMarch<Real> m;
    Real numLayers = glslMix(Real(cfg.maxLayers), Real(cfg.minLayers), std::fabs(v.z));
    m.layerDepth = Real(1) / numLayers;
    m.layer = Real(0);
    Vec2<Real> p = Vec2<Real>(v.x, v.y) / v.z * c.scale;
    m.delta = p / numLayers;
    m.uv = reliefTopEntry(uv0, v, c.scale, c.bias);
    m.depthValue = c.depth(m.uv);
    int limit = cfg.maxSteps > 0 ? cfg.maxSteps : kSafetyStepCap;
    int steps = 0;
    while (m.layer < m.depthValue) {
        if (steps == limit) {
            c.flags |= kFlagStepLimit;
            break;
        }
        m.uv -= m.delta;
        m.depthValue = c.depth(m.uv);
        m.layer += m.layerDepth;
        ++steps;
    }
    return m;
}

// The height of the eye ray at march depth t in [0, 1] below the top of the relief: the ray
// enters at s + b (t = 0) and leaves at b (t = 1) (docs/model.md §6c).
template <class Real>
inline Real marchHeight(const MethodContext<Real>& c, Real t) {
    return c.scale + c.bias - c.scale * t;
}

template <class Real>
Vec2<Real> methodSteep(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                       const BuiltinMethod& method) {
    SteepMarch<Real> m = steepMarch(c, uv0, v, method.as<LayerParameters>());
    c.foundHeight = marchHeight(c, m.layer);
    return m.uv;
}

// LearnOpenGL/the deferred-renderer blog tail: interpolate between the layers before and after the
// crossing.
template <class Real>
Vec2<Real> methodPom(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                     const BuiltinMethod& method) {
    SteepMarch<Real> m = steepMarch(c, uv0, v, method.as<LayerParameters>());
    Vec2<Real> prev = m.uv + m.delta;
    Real after = m.depthValue - m.layer;
    Real before = c.depth(prev) - m.layer + m.layerDepth;
    Real denom = after - before;
    if (denom == Real(0)) c.flags |= kFlagZeroDivide;  // 0/0 or x/0: w is not finite
    Real w = after / denom;
    c.foundHeight = marchHeight(c, m.layer - m.layerDepth * w);
    return prev * w + m.uv * (Real(1) - w);
}

// Policarpo et al. 2005 ray_intersect_rm: linear search over linear_steps - 1 depths (the
// first crossing only: best > 0.996 means none yet), then binary_steps halvings. Every fetch
// runs, as in the shader.
template <class Real>
Vec2<Real> methodRelief(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                        const BuiltinMethod& method) {
    const auto& cfg = method.as<ReliefParameters>();
    Vec2<Real> dp = reliefTopEntry(uv0, v, c.scale, c.bias);
    Vec2<Real> ds = -Vec2<Real>(v.x, v.y) / v.z * c.scale;
    Real size = Real(1) / Real(cfg.linearSteps);
    Real depth = Real(0);
    Real best = Real(1);
    for (int i = 0; i < cfg.linearSteps - 1; ++i) {
        depth += size;
        Real t = c.depth(dp + ds * depth);
        if (best > Real(0.996))
            if (depth >= t) best = depth;
    }
    depth = best;
    for (int i = 0; i < cfg.binarySteps; ++i) {
        size *= Real(0.5);
        Real t = c.depth(dp + ds * depth);
        if (depth >= t) {
            best = depth;
            depth -= Real(2) * size;
        }
        depth += size;
    }
    c.foundHeight = marchHeight(c, best);
    return dp + ds * best;
}

}  // namespace pgt
