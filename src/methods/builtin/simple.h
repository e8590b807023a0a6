// The single-fetch methods: none, parallax (Welsh 2004 §4.1) and offset limiting (Welsh 2004 §4.3).
#pragma once

#include "methods/method.h"

namespace pgt {

// Normal-mapping baseline: uv' = uv0.
template <class Real>
Vec2<Real> methodNone(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real>, const BuiltinMethod&) {
    c.foundHeight = Real(0);  // the base surface itself
    return uv0;
}

// Welsh 2004 §4.1, ARB fragment program: MAD h*s+b; RCP V.z; MUL; MAD offset*V.xy + T0.
template <class Real>
Vec2<Real> methodParallax(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                          const BuiltinMethod&) {
    Real height = c.h(uv0) * c.scale + c.bias;
    c.foundHeight = height;
    Real rcpZ = Real(1) / v.z;
    height = height * rcpZ;
    return height * Vec2<Real>(v.x, v.y) + uv0;
}

// Welsh 2004 §4.3: Tn = To + hsb * V.xy (no division by V.z).
template <class Real>
Vec2<Real> methodOffsetLimited(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                               const BuiltinMethod&) {
    Real height = c.h(uv0) * c.scale + c.bias;
    c.foundHeight = height;  // the height it used (docs/model.md §6c), not on the eye ray
    return height * Vec2<Real>(v.x, v.y) + uv0;
}

}  // namespace pgt
