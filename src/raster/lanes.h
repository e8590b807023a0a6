// Arithmetic over a group of pixels at once for the rasteriser's shading (raster.cpp): one
// value a pixel ("lane") in each array, component by component. Each function does what glm
// does to one pixel's vector, with the same operations in the same order (dot: (x + y) + z;
// normalize: v * (1 / sqrt(dot(v, v))); cross; a triangle's interpolation:
// (c0 b0 + c1 b1) + c2 b2), so that every lane has glm's bits while the compiler packs the
// lanes into vector registers. Internal to raster/.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "core/math.h"

namespace pgt::raster_detail {

constexpr size_t kLanes = 8;
using Lanes = std::array<double, kLanes>;
struct Lanes3 {
    Lanes x, y, z;
    Vec3d at(size_t l) const { return {x[l], y[l], z[l]}; }
};

inline Lanes dot(const Lanes3& a, const Lanes3& b) {
    Lanes r;
    for (size_t l = 0; l < kLanes; ++l) r[l] = a.x[l] * b.x[l] + a.y[l] * b.y[l] + a.z[l] * b.z[l];
    return r;
}

inline void normalize(Lanes3& v) {
    const Lanes d = dot(v, v);
    for (size_t l = 0; l < kLanes; ++l) {
        const double inv = 1.0 / std::sqrt(d[l]);
        v.x[l] *= inv, v.y[l] *= inv, v.z[l] *= inv;
    }
}

// cross(a, b) times `sign` (+-1) per lane.
inline Lanes3 cross(const Lanes3& a, const Lanes3& b, const Lanes& sign) {
    Lanes3 r;
    for (size_t l = 0; l < kLanes; ++l) {
        r.x[l] = (a.y[l] * b.z[l] - b.y[l] * a.z[l]) * sign[l];
        r.y[l] = (a.z[l] * b.x[l] - b.z[l] * a.x[l]) * sign[l];
        r.z[l] = (a.x[l] * b.y[l] - b.x[l] * a.y[l]) * sign[l];
    }
    return r;
}

// A vertex attribute's component (c0, c1, c2) at the lanes' barycentrics b[0..2].
inline Lanes interpolate(double c0, double c1, double c2, const std::array<Lanes, 3>& b) {
    Lanes r;
    for (size_t l = 0; l < kLanes; ++l) r[l] = c0 * b[0][l] + c1 * b[1][l] + c2 * b[2][l];
    return r;
}
inline Lanes3 interpolate(const Vec3d& c0, const Vec3d& c1, const Vec3d& c2,
                          const std::array<Lanes, 3>& b) {
    return {interpolate(c0.x, c1.x, c2.x, b), interpolate(c0.y, c1.y, c2.y, b),
            interpolate(c0.z, c1.z, c2.z, b)};
}

}  // namespace pgt::raster_detail
