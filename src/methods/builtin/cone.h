// Cone step mapping (Dummer 2006) on pgt's conservative cone map (heightfield/cone_map.h).
#pragma once

#include <cmath>

#include "heightfield/cone_map.h"
#include "methods/method.h"

namespace pgt {

// The eye ray of cone and relaxed_cone over heights e (below): uv(e) = uv0 + dir (a e + b).
template <class Real>
struct ConeRay {
    Vec2<Real> uv0, dir;
    Real sign, a, b, r;  // e = sign h; a = |s|; r = UV travelled per unit of e
    ConeRay(const ConeMap& m, const MethodContext<Real>& c, Vec2<Real> uv, Vec3<Real> v)
        : uv0(uv),
          dir(Vec2<Real>(v.x, v.y) / v.z),
          sign(m.inverted ? Real(-1) : Real(1)),
          a(std::fabs(c.scale)),
          b(c.bias),
          r(a * std::sqrt(dir.x * dir.x + dir.y * dir.y)) {}
    Vec2<Real> at(Real e) const { return uv0 + dir * (a * e + b); }
    // uv' at e, its height a e + b the found point's (docs/model.md §6c).
    Vec2<Real> found(MethodContext<Real>& c, Real e) const {
        c.foundHeight = a * e + b;
        return at(e);
    }
};

// Whether the eye is above the surface (V.z > 0); if not there is no first hit: flagged.
template <class Real>
bool eyeAbove(MethodContext<Real>& c, Vec3<Real> v) {
    if (v.z > Real(0)) return true;
    c.flags |= kFlagZeroDivide;
    return false;
}

// The ray in heights e (e = h, or -h when s < 0; heightfield/cone_map.h): uv(e) = uv0 + V.xy /
// V.z * (|s| e + b), from the map's top e down. It moves r = |s| |V.xy / V.z| in UV per unit
// of e. A cone step from uv with the surface at e_s below the ray's e and the cell's ratio c
// descends c (e - e_s) / (c + r): to where the ray meets the cone of apex (uv, e_s), which
// holds no surface (Dummer 2006, §3; his dist = r and height = e - e_s). `steps` cone steps
// (32), each two fetches (the height, the cell's ratio), stopping on the surface; then
// `refine_steps` (5) bisections of [e, e - (e - e_s)] (from the last point down to where the
// ray meets the height below it), one fetch each plus one for that height; uv' = the
// bisection's middle, or the last cone point without refinement. Pure cone stepping
// (refine_steps 0) never passes the first intersection.
template <class Real>
Vec2<Real> methodCone(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                      const BuiltinMethod& method) {
    const auto& cfg = method.as<ConeParameters>();
    const ConeMap& m = *c.cone;
    if (!eyeAbove(c, v)) return Vec2<Real>(NAN);
    const ConeRay<Real> ray(m, c, uv0, v);
    const Real sign = ray.sign;
    Real e = Real(m.top);
    Vec2<Real> uv = ray.at(e);
    for (int i = 0; i < cfg.steps; ++i) {
        const Real gap = e - sign * c.h(uv);
        if (!(gap > Real(0))) break;  // on the surface (or a NaN height)
        ++c.fetches;
        const Real ratio = Real(m.ratio[size_t(coneCell(m, uv.x, uv.y))]);
        e -= ratio * gap / (ratio + ray.r);
        uv = ray.at(e);
    }
    if (cfg.refineSteps == 0) return ray.found(c, e);
    const Real gap = e - sign * c.h(uv);
    if (!(gap > Real(0))) return ray.found(c, e);
    Real above = e, below = e - gap;
    for (int i = 0; i < cfg.refineSteps; ++i) {
        const Real mid = (above + below) * Real(0.5);
        (mid - sign * c.h(ray.at(mid)) > Real(0) ? above : below) = mid;
    }
    return ray.found(c, (above + below) * Real(0.5));
}

// Relaxed cone stepping (Policarpo & Oliveira, GPU Gems 3 ch. 18, listing 18-3) on the relaxed
// cone map (heightfield/cone_map.h, one ratio per texel, read at the nearest texel): the
// same ray and cone step as cone, with the height gap saturated at 0 (a ray inside the surface
// stays where it is), `cone_steps` (15) times, two fetches each; then `binary_steps` (6)
// halvings over the whole way travelled, from its middle (the book's v *= p.z * 0.5; p = p0 +
// v): deeper where the point is above the surface, back up where not; one fetch each.
template <class Real>
Vec2<Real> methodRelaxedCone(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                             const BuiltinMethod& method) {
    const auto& cfg = method.as<RelaxedConeParameters>();
    const ConeMap& m = *c.relaxedCone;
    if (!eyeAbove(c, v)) return Vec2<Real>(NAN);
    const ConeRay<Real> ray(m, c, uv0, v);
    const Real top = Real(m.top);
    Real e = top;
    for (int i = 0; i < cfg.coneSteps; ++i) {
        const Vec2<Real> uv = ray.at(e);
        const Real gap = std::max(e - ray.sign * c.h(uv), Real(0));
        ++c.fetches;
        const Real ratio = Real(m.ratio[size_t(relaxedTexel(m, uv.x, uv.y))]);
        e -= ratio * gap / (ratio + ray.r);
    }
    Real half = (top - e) * Real(0.5), mid = top - half;
    for (int i = 0; i < cfg.binarySteps; ++i) {
        half *= Real(0.5);
        mid += mid - ray.sign * c.h(ray.at(mid)) > Real(0) ? -half : half;
    }
    return ray.found(c, mid);
}

}  // namespace pgt
