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

inline constexpr double kPi = 3.14159265358979323846;

inline double radians(double degrees) { return degrees * (kPi / 180.0); }
inline double degrees(double radians) { return radians * (180.0 / kPi); }

template <class V>
bool allFinite(const V& v) {
    for (int i = 0; i < V::length(); ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace pgt
