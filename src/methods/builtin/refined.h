// Searches that refine a linear march without a precomputed map: the secant method (Risser,
// Shah, Pattanaik, "Faster Relief Mapping Using the Secant Method", JGT 12(3), 2007) and
// contact refinement (A. Riccardi, "Contact refinement parallax mapping", 2018). Both use
// the ray of relief mapping (methods/builtin/layered.h): uv(t) = dp + ds * t, t in [0, 1] the depth
// below the top of the relief, d = 1 - h the depth map (docs/model.md §6b).
#pragma once

#include <cmath>

#include "methods/builtin/layered.h"
#include "methods/method.h"

namespace pgt {

// Secant (Risser et al. 2007, §3): a linear search for the first t with t >= d(uv(t)),
// stepping 1/linear_steps from t = 0, brackets the crossing between the last sample above
// the surface (f = d - t > 0) and the first one on or below it (f <= 0); then secant_steps
// times the secant of f through the bracket's ends, t = ta + (tb - ta) * fa / (fa - fb),
// replacing the end of the same sign. uv' = uv(last secant t), or uv(t) of the linear
// search when secant_steps is 0 or no sample lies below the surface.
template <class Real>
Vec2<Real> methodSecant(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                        const BuiltinMethod& method) {
    const auto& cfg = method.as<SecantParameters>();
    const Vec2<Real> dp = reliefTopEntry(uv0, v, c.scale, c.bias);
    const Vec2<Real> ds = -Vec2<Real>(v.x, v.y) / v.z * c.scale;
    const Real size = Real(1) / Real(cfg.linearSteps);
    Real ta = Real(0), fa = c.depth(dp);
    auto found = [&](Real t) {
        c.foundHeight = marchHeight(c, t);
        return dp + ds * t;
    };
    if (!(fa > Real(0))) return found(Real(0));  // the top of the relief is on the surface
    Real tb = ta, fb = fa;
    for (int i = 0; i < cfg.linearSteps; ++i) {
        tb = ta + size;
        fb = c.depth(dp + ds * tb) - tb;
        if (!(fb > Real(0))) break;
        ta = tb, fa = fb;
    }
    if (fb > Real(0)) return found(tb);  // no sample below the surface (h below 0)
    Real t = tb;
    for (int i = 0; i < cfg.secantSteps; ++i) {
        t = ta + (tb - ta) * fa / (fa - fb);  // fa > 0 >= fb: no division by zero
        Real f = c.depth(dp + ds * t) - t;
        if (f > Real(0))
            ta = t, fa = f;
        else
            tb = t, fb = f;
    }
    return found(t);
}

// Contact refinement (Riccardi 2018): the steep march of methods/builtin/layered.h with a fixed
// `layers` count n; one step back from the first layer below the surface; a second n-layer
// march inside that step (step and layer depth divided by n); then pom's interpolation
// between the second march's last two layers (docs/model.md §6b pom, with the finer step).
template <class Real>
Vec2<Real> methodContact(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                         const BuiltinMethod& method) {
    const auto& cfg = method.as<ContactParameters>();
    const Real n = Real(cfg.layers);
    Real layerDepth = Real(1) / n;
    Vec2<Real> delta = Vec2<Real>(v.x, v.y) / v.z * c.scale / n;
    Vec2<Real> uv = reliefTopEntry(uv0, v, c.scale, c.bias);
    Real layer = Real(0);
    Real depthValue = c.depth(uv);
    auto march = [&](int limit) {
        for (int steps = 0; layer < depthValue; ++steps) {
            if (steps == limit) {
                c.flags |= kFlagStepLimit;
                return;
            }
            uv -= delta;
            depthValue = c.depth(uv);
            layer += layerDepth;
        }
    };
    march(kSafetyStepCap);
    if (layer > Real(0)) {  // one step back, then the fine march inside that step
        uv += delta;
        layer -= layerDepth;
        delta /= n;
        layerDepth /= n;
        depthValue = c.depth(uv);
        march(kSafetyStepCap);
    }
    Vec2<Real> prev = uv + delta;
    Real after = depthValue - layer;
    Real before = c.depth(prev) - layer + layerDepth;
    Real denom = after - before;
    if (denom == Real(0)) c.flags |= kFlagZeroDivide;
    Real w = after / denom;
    c.foundHeight = marchHeight(c, layer - layerDepth * w);
    return prev * w + uv * (Real(1) - w);
}

}  // namespace pgt
