// Self-shadowing from the point a method found toward the view's directional light
// (docs/model.md §6c): the hard march of the POM literature (the parallax-mapping encyclopedia
// article: "a secondary raymarch ... along the light direction ... if any sample height exceeds the
// light ray's accumulated depth, the fragment is considered occluded") and Tatarchuk's soft shadow
// (Dynamic Parallax Occlusion Mapping with Approximate Soft Shadows, I3D 2006; the DirectX SDK
// sample's seven weighted height differences). Both read the height map through the method's
// context; the pipeline records the method's fetches before the march (docs/model.md §6c: a march
// is not in the method's cost).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/samples.h"
#include "methods/method.h"

namespace pgt {

// The hard march: from (uv', z0), z0 the found height, `shadow_steps` samples evenly spaced in
// height up to the top of the relief (s + b, or b when s < 0), along the light's tangent-space
// direction L: uv_k = uv' + L.xy / L.z * (z_k - z0). In shadow when the surface at a sample
// lies above the light ray there (s h(uv_k) + b > z_k), or when the light is at or below the
// base's horizon (L.z <= 0). A found point at or above the top is lit.
template <class Real>
int8_t hardShadow(MethodContext<Real>& c, Vec2<Real> uv, Real z0, Vec3<Real> light, int steps) {
    if (!(light.z > Real(0))) return kShadowDark;
    const Real top = c.scale >= Real(0) ? c.scale + c.bias : c.bias;
    if (!(z0 < top)) return kShadowLit;  // also a NaN height: nothing to march from
    // Each sample's height from k directly, not by adding dz k times: the float sum can end
    // below the top (a spurious shadow on a plateau at the top height), k = n is the top itself.
    const Real rise = top - z0;
    const Vec2<Real> slope = Vec2<Real>(light.x, light.y) / light.z;
    for (int k = 1; k <= steps; ++k) {
        const Real dz = k == steps ? rise : rise * Real(k) / Real(steps);
        const Real z = k == steps ? top : z0 + dz;
        if (c.h(uv + slope * dz) * c.scale + c.bias > z) return kShadowDark;
    }
    return kShadowLit;
}

// Tatarchuk 2006 as the DirectX SDK sample ships it: h0 = h(uv'), seven samples at
// uv' + L.xy * s * f for f = 0.88, 0.77, ..., 0.22, each (h - h0 - f) weighted 1, 2, 4, 6, 8,
// 10, 12 and by the softening (0.58); the light reaching the point is 1 - the largest. It
// offsets by L.xy without dividing by L.z and compares heights in [0, 1], whatever the bias
// (the sample's map is a height map with the relief below the polygon). pgt counts it as in
// shadow where less than half the light arrives (docs/model.md §6c); L.z <= 0 is in shadow.
template <class Real>
int8_t softShadow(MethodContext<Real>& c, Vec2<Real> uv, Vec3<Real> light, Real softening) {
    if (!(light.z > Real(0))) return kShadowDark;
    static constexpr float kWeights[7] = {1, 2, 4, 6, 8, 10, 12};
    const Vec2<Real> ray = Vec2<Real>(light.x, light.y) * c.scale;
    const Real h0 = c.h(uv);
    Real occlusion = -INFINITY;
    for (int i = 0; i < 7; ++i) {
        const Real f = Real(0.88) - Real(0.11) * Real(i);
        occlusion =
            std::max(occlusion, (c.h(uv + ray * f) - h0 - f) * Real(kWeights[i]) * softening);
    }
    return Real(1) - occlusion < Real(0.5) ? kShadowDark : kShadowLit;
}

// The configured march from the method's answer (uv', c.foundHeight).
template <class Real>
int8_t runShadow(const BuiltinMethod& cfg, MethodContext<Real>& c, Vec2<Real> uv,
                 Vec3<Real> light) {
    switch (cfg.shadow) {
        case ShadowMarch::Hard:
            return hardShadow(c, uv, c.foundHeight, light, cfg.shadowSteps);
        case ShadowMarch::Soft:
            return softShadow(c, uv, light, Real(cfg.shadowSoftening));
        case ShadowMarch::None:
            break;
    }
    return kShadowNone;
}

}  // namespace pgt
