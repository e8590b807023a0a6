// Premecz 2006, iterative parallax mapping with slope information (as Szirmay-Kalos and
// Umenhoffer's 2008 survey presents it): the eye ray's point climbs toward each tangent plane
// in turn, on Lengyel FGED 2's unit normal map of the scaled height field (Eq. 7.41-7.43).
#pragma once

#include "methods/method.h"

namespace pgt {

// The point p = (uv, z) on the eye ray starts on the polygon, (uv0, 0). `iterations` times,
// with H = s h + b and n the normal map, both read at p's uv (two fetches, docs/model.md §6b;
// the survey packs them in one RGBA texel), p moves along V by (H - z) n_z: toward the tangent
// plane through (uv, H) with dot(n, V) taken as 1, as offset limiting drops its 1 / V.z. The
// filtered normal is used as read (not renormalised), as the survey's listing uses its texel.
template <class Real>
Vec2<Real> methodIterativeSlope(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                                const BuiltinMethod& method) {
    const auto& cfg = method.as<IterationParameters>();
    Vec2<Real> uv = uv0;
    Real z = Real(0);
    for (int i = 0; i < cfg.iterations; ++i) {
        const Vec3<Real> n = c.normalMap(uv);
        const Real h = c.h(uv);
        const Real step = (h * c.scale + c.bias - z) * n.z;
        uv += Vec2<Real>(v.x, v.y) * step;
        z += v.z * step;
    }
    c.foundHeight = z;  // the ray point's height (docs/model.md §6c)
    return uv;
}

}  // namespace pgt
