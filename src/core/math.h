// Vector types (GLM) and small numeric helpers shared by every stage.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

namespace pgt {

template <class Real>
using Vec2 = glm::vec<2, Real, glm::defaultp>;
template <class Real>
using Vec3 = glm::vec<3, Real, glm::defaultp>;

using Vec2f = Vec2<float>;
using Vec3f = Vec3<float>;
using Vec2d = Vec2<double>;
using Vec3d = Vec3<double>;
using Vec2i = glm::vec<2, int, glm::defaultp>;

inline constexpr double kPi = 3.14159265358979323846;

inline double radians(double degrees) { return degrees * (kPi / 180.0); }
inline double degrees(double radians) { return radians * (180.0 / kPi); }

// sin and cos of an angle in degrees, exact at every multiple of 90 (cos 90 is 0, not the
// 6.1e-17 of cos(pi / 2) in double): a light or a view at 90 degrees lies exactly in the plane,
// and axis-aligned views (phi 0, 90, 180, 270) have exactly zero cross components.
// Elsewhere they are std::sin and std::cos of radians(degrees), unchanged.
inline double sinDegrees(double degrees) {
    if (std::fmod(degrees, 90.0) == 0) {
        const int q = int(std::fmod(degrees, 360.0) / 90.0) & 3;  // quadrant 0..3
        return q == 1 ? 1.0 : q == 3 ? -1.0 : 0.0;
    }
    return std::sin(radians(degrees));
}
inline double cosDegrees(double degrees) {
    if (std::fmod(degrees, 90.0) == 0) return sinDegrees(degrees + 90.0);
    return std::cos(radians(degrees));
}

template <class V>
bool allFinite(const V& v) {
    for (int i = 0; i < V::length(); ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace pgt
