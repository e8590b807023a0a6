// Lengyel, FGED vol. 2: iterative parallax (Listing 7.9, Eq. 7.51-7.52) and the
// tangent-plane offset (Eq. 7.50), on the normal and parallax maps of Eq. 7.41-7.43
// (heightfield/heightfield.h makeDerivedMaps).
#pragma once

#include <cmath>

#include "methods/method.h"

namespace pgt {

// Lengyel FGED 2 Listing 7.9 with k = iterations: pdir = V.xy * scale; k times texcoord += pdir *
// P. Our P already holds s (UV units) and the bias, so scale = 1/k (Eq. 7.52 without s, r, 2).
template <class Real>
Vec2<Real> methodIterative(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                           const BuiltinMethod& method) {
    const auto& cfg = method.as<IterationParameters>();
    Vec2<Real> pdir = Vec2<Real>(v.x, v.y) / Real(cfg.iterations);
    Vec2<Real> uv = uv0;
    Real sum = Real(0);
    for (int i = 0; i < cfg.iterations; ++i) {
        Real parallax = c.parallaxMap(uv);
        uv += pdir * parallax;
        sum += parallax;
    }
    c.foundHeight = sum / Real(cfg.iterations);  // the mean height it used (docs/model.md §6c)
    return uv;
}

// Lengyel FGED 2 Eq. 7.50: offset = V.xy * (n_z h) / dot(n, V) with n the normalised bilinear
// normal.
template <class Real>
Vec2<Real> methodTangentPlane(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                              const BuiltinMethod&) {
    Vec3<Real> n = glm::normalize(c.normalMap(uv0));
    Real parallax = c.parallaxMap(uv0);
    Real ndotv = glm::dot(n, v);
    if (!(ndotv > Real(0))) c.flags |= kFlagZeroDivide;  // plane faces away or is edge-on
    const Real along = parallax / ndotv;  // the eye ray's parameter at the tangent plane
    c.foundHeight = along * v.z;
    return uv0 + Vec2<Real>(v.x, v.y) * along;
}

}  // namespace pgt
