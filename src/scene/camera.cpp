// Camera bases and pixel rays (docs/model.md §4).
#include "scene/camera.h"

#include <algorithm>
#include <cmath>

namespace pgt {

Vec3d viewFromAngles(double thetaDegrees, double phiDegrees) {
    // Exact at multiples of 90 degrees (a light at the horizon, axis-aligned views).
    const double st = sinDegrees(thetaDegrees), ct = cosDegrees(thetaDegrees);
    return {st * cosDegrees(phiDegrees), st * sinDegrees(phiDegrees), ct};
}

Camera Camera::make(bool ortho, Vec3d forward, Vec3d target, Vec3d up, double halfHeight, int width,
                    int height) {
    Camera c;
    c.ortho_ = ortho;
    c.width_ = width;
    c.height_ = height;
    c.target_ = target;
    c.forward_ = glm::normalize(forward);
    c.right_ = glm::normalize(glm::cross(c.forward_, up));
    c.up_ = glm::cross(c.right_, c.forward_);
    c.halfHeight_ = halfHeight;
    c.halfWidth_ = halfHeight * width / height;
    return c;
}

Camera Camera::pinhole(Vec3d eye, Vec3d target, Vec3d up, double fovDegrees, int width,
                       int height) {
    Camera c =
        make(false, target - eye, target, up, std::tan(radians(fovDegrees) / 2), width, height);
    c.eye_ = eye;
    c.fovDegrees_ = fovDegrees;
    return c;
}

Camera Camera::orthographic(Vec3d dir, Vec3d target, Vec3d up, double viewHeight, int width,
                            int height) {
    return make(true, dir, target, up, viewHeight / 2, width, height);
}

Ray Camera::ray(double sx, double sy) const {
    double x = (2 * sx / width_ - 1) * halfWidth_;
    double y = (1 - 2 * sy / height_) * halfHeight_;
    if (ortho_) return {target_ + right_ * x + up_ * y, forward_, true};
    return {eye_, glm::normalize(forward_ + right_ * x + up_ * y), false};
}

Vec2d Camera::jitteredSample(int px, int py) const {
    // A 64-bit mix (splitmix64 finaliser) of pixel and seed -> two uniforms in (0, 1).
    uint64_t z = (uint64_t(uint32_t(px)) << 32 | uint32_t(py)) ^
                 (uint64_t(jitterSeed_) * 0x9E3779B97F4A7C15ull);
    auto next = [&z]() {
        z += 0x9E3779B97F4A7C15ull;
        uint64_t x = z;
        x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
        x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
        x ^= x >> 31;
        return (double(x >> 11) + 0.5) / 9007199254740992.0;  // 2^53
    };
    double jx = next(), jy = next();
    return {px + jx, py + jy};
}

Vec3d Camera::toCamera(Vec3d world) const {
    Vec3d d = world - (ortho_ ? target_ : eye_);
    return {glm::dot(d, right_), glm::dot(d, up_), glm::dot(d, forward_)};
}

Vec2d Camera::toScreen(Vec3d cam) const {
    double x = cam.x, y = cam.y;
    if (!ortho_) x /= cam.z, y /= cam.z;
    return {(x / halfWidth_ + 1) * width_ / 2, (1 - y / halfHeight_) * height_ / 2};
}

Vec3d Camera::viewVector(Vec3d world) const {
    if (ortho_) return -forward_;
    return glm::normalize(eye_ - world);
}

int tilesToCover(const Camera& camera, Vec3d center, double size, int cap) {
    double reach = 0;
    const int w = camera.width(), hgt = camera.height();
    const double xs[3] = {0.0, w / 2.0, double(w)}, ys[3] = {0.0, hgt / 2.0, double(hgt)};
    for (double sx : xs)
        for (double sy : ys) {
            Ray r = camera.ray(sx, sy);
            if (r.dir.z == 0) return cap;
            double t = (center.z - r.origin.z) / r.dir.z;
            if (t < 0 && !r.line) return cap;  // this corner looks above the horizon
            Vec3d p = r.origin + r.dir * t - center;
            reach = std::max({reach, std::fabs(p.x), std::fabs(p.y)});
        }
    return int(std::min(double(cap), std::ceil(reach / size - 0.5) + 1));
}

}  // namespace pgt
