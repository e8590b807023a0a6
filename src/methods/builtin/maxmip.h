// Exact tracing over the minimum-maximum pyramid (Tevs, Ihrke, Seidel, "Maximum Mipmaps
// for Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008, §4; Drobot's
// Quadtree Displacement Mapping, GPU Pro 2010, walks the same tree on depth): the eye ray
// descends into a node where it reaches the node's box [cells] x [lowest, highest height]
// and passes over it otherwise; in a single cell it meets the cell's bilinear patch exactly
// (docs/model.md §1: along the ray the patch is a quadratic in the ray parameter), so uv' lies on
// the very surface the truth traces, up to the arithmetic's rounding.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "heightfield/minmax_pyramid.h"
#include "methods/method.h"

namespace pgt {

namespace maxmip {

// floor(a / 2) for any integer.
inline int64_t half(int64_t a) { return a >= 0 ? a / 2 : -((-a + 1) / 2); }

// The smallest sigma in [0, sigma1] where C + B sigma + A sigma^2 <= 0 (the ray at or below
// the patch), or false. The quadratic's roots in the cancellation-free form; where rounding
// hides a sign change the end test catches it and bisection finds the crossing.
template <class Real>
bool firstRoot(Real A, Real B, Real C, Real sigma1, Real& sigma) {
    if (!(C > Real(0))) {
        sigma = Real(0);
        return true;
    }
    Real best = INFINITY;
    auto consider = [&](Real r) {
        if (r >= Real(0) && r <= sigma1 && r < best) best = r;
    };
    if (A == Real(0)) {
        if (B < Real(0)) consider(-C / B);
    } else {
        const Real disc = B * B - Real(4) * A * C;
        if (disc >= Real(0)) {
            const Real q = Real(-0.5) * (B + std::copysign(std::sqrt(disc), B));
            consider(q / A);
            if (q != Real(0)) consider(C / q);
        }
    }
    if (best <= sigma1) {
        sigma = best;
        return true;
    }
    auto F = [&](Real x) { return C + (B + A * x) * x; };
    if (!(F(sigma1) <= Real(0))) return false;
    Real lo = Real(0), hi = sigma1;  // F(lo) > 0 >= F(hi)
    for (int k = 0; k < 64 && lo < hi; ++k) {
        const Real mid = lo + (hi - lo) * Real(0.5);
        if (mid <= lo || mid >= hi) break;
        (F(mid) > Real(0) ? lo : hi) = mid;
    }
    sigma = hi;
    return true;
}

}  // namespace maxmip

// The ray: uv(z) = uv0 + V.xy / V.z * z for heights z from the top of the relief (s * max h
// + b; s * min h + b when s < 0) down to its bottom, where it must have met the surface. In
// texel-centre lattice units (x = u W - 0.5) it is X(tau) = X0 + dX tau with tau = zTop - z.
// Fetches: one per pyramid node read (the top one for the map's range first) and four per
// cell patch (its corners). Each node
// visited is one of max_iterations; the bound reached is flagged as a step limit.
template <class Real>
Vec2<Real> methodMaxMip(MethodContext<Real>& c, Vec2<Real> uv0, Vec3<Real> v,
                        const BuiltinMethod& method) {
    const auto& cfg = method.as<MaxMipParameters>();
    const MinMaxPyramid& p = *c.pyramid;
    const Real s = c.scale, b = c.bias;
    const Vec2<Real> dir = Vec2<Real>(v.x, v.y) / v.z;
    if (!(v.z > Real(0))) {
        c.flags |= kFlagZeroDivide;  // the eye is not above the surface: no first hit
        return Vec2<Real>(NAN);
    }
    ++c.fetches;  // the map's range: the pyramid's top node
    const Real zTop = s >= Real(0) ? s * Real(p.hi) + b : s * Real(p.lo) + b;
    const Real zBot = s >= Real(0) ? s * Real(p.lo) + b : s * Real(p.hi) + b;
    const Real W = Real(p.width), H = Real(p.height);
    const Vec2<Real> start = uv0 + dir * zTop;
    const Real X0 = start.x * W - Real(0.5), Y0 = start.y * H - Real(0.5);
    const Real dX = -dir.x * W, dY = -dir.y * H;
    const Real tauMax = zTop - zBot;
    auto at = [&](Real tau) {
        c.foundHeight = zTop - tau;  // the ray's height there (docs/model.md §6c)
        return uv0 + dir * (zTop - tau);
    };
    if (!(std::fabs(X0) < Real(1 << 30) && std::fabs(Y0) < Real(1 << 30))) return at(tauMax);
    int level = p.top();
    int64_t nx = int64_t(std::floor(X0)) >> level, ny = int64_t(std::floor(Y0)) >> level;
    Real tau = Real(0);
    for (int iteration = 0;; ++iteration) {
        if (iteration == cfg.maxIterations) {
            c.flags |= kFlagStepLimit;
            return at(tau);
        }
        const int64_t size = int64_t(1) << level;
        const Real tx = dX > Real(0)   ? (Real((nx + 1) * size) - X0) / dX
                        : dX < Real(0) ? (Real(nx * size) - X0) / dX
                                       : Real(INFINITY);
        const Real ty = dY > Real(0)   ? (Real((ny + 1) * size) - Y0) / dY
                        : dY < Real(0) ? (Real(ny * size) - Y0) / dY
                                       : Real(INFINITY);
        const Real tExit = std::min(tx, ty);
        float lo, hi;
        latticeBounds(p, nx * size, ny * size, size, lo, hi, c.fetches);
        const Real zMax = s >= Real(0) ? s * Real(hi) + b : s * Real(lo) + b;
        const Real tEnter = std::max(tau, zTop - zMax);  // where the ray reaches the box top
        if (tEnter < tExit) {
            if (level > 0) {  // into the child the ray is in at tEnter
                tau = tEnter;
                --level;
                const Real x = X0 + dX * tau, y = Y0 + dY * tau;
                const int64_t half = int64_t(1) << level;
                nx = 2 * nx + ((x > Real((2 * nx + 1) * half) ||
                                (x == Real((2 * nx + 1) * half) && dX > Real(0)))
                                   ? 1
                                   : 0);
                ny = 2 * ny + ((y > Real((2 * ny + 1) * half) ||
                                (y == Real((2 * ny + 1) * half) && dY > Real(0)))
                                   ? 1
                                   : 0);
                continue;
            }
            // One cell: its bilinear patch along the ray, sigma = tau - tEnter.
            int i0, i1, j0, j1;
            Real fx, fy;
            detail::texelPair(Real(nx), p.width, p.address, i0, i1, fx);
            detail::texelPair(Real(ny), p.height, p.address, j0, j1, fy);
            const Texture& t = *c.height;
            const Real h00 = Real(t.texel(i0, j0)), h10 = Real(t.texel(i1, j0));
            const Real h01 = Real(t.texel(i0, j1)), h11 = Real(t.texel(i1, j1));
            c.fetches += 4;
            const Real ax = X0 + dX * tEnter - Real(nx), ay = Y0 + dY * tEnter - Real(ny);
            const Real e = h10 - h00, f = h01 - h00, g = h00 - h10 - h01 + h11;
            const Real h0 = h00 + e * ax + f * ay + g * ax * ay;
            const Real h1 = e * dX + f * dY + g * (ax * dY + ay * dX);
            const Real h2 = g * dX * dY;
            const Real sigma1 = std::min(tExit, tauMax) - tEnter;
            Real sigma;
            if (maxmip::firstRoot(-s * h2, Real(-1) - s * h1, zTop - tEnter - b - s * h0,
                                  std::max(sigma1, Real(0)), sigma))
                return at(tEnter + sigma);
        }
        if (tExit >= tauMax) return at(tauMax);  // rounding: the bottom, where h is lowest
        // Past the node: to its neighbour, up a level where that leaves the parent (never
        // back up into a parent the ray is still in, which rounding at a child's edge could
        // send down into the child just left).
        tau = std::max(tau, tExit);
        const int64_t px = maxmip::half(nx), py = maxmip::half(ny);
        if (tx <= ty) nx += dX > Real(0) ? 1 : -1;
        if (ty <= tx) ny += dY > Real(0) ? 1 : -1;
        if (level < p.top() && (maxmip::half(nx) != px || maxmip::half(ny) != py)) {
            ++level;
            nx = maxmip::half(nx);
            ny = maxmip::half(ny);
        }
    }
}

}  // namespace pgt
