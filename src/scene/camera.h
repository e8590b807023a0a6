// Cameras (docs/model.md §4): pinhole and orthographic, one ray per pixel centre. Pixel (x, y)
// has x to the right and y DOWN from the top-left; its ray passes through (x + 0.5, y + 0.5).
// The rasteriser uses project() and the truth uses ray(): both come from the same basis.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace pgt {

struct Ray {
    Vec3d origin;
    Vec3d dir;          // unit length
    bool line = false;  // orthographic: the eye is at infinity, the whole line counts
};

class Camera {
  public:
    // Pinhole: vertical field of view in degrees.
    static Camera pinhole(Vec3d eye, Vec3d target, Vec3d up, double fovDegrees, int width,
                          int height);
    // Orthographic looking along `dir`, image centre at `target`, `viewHeight` world units
    // tall, with `up` projected to the image plane.
    static Camera orthographic(Vec3d dir, Vec3d target, Vec3d up, double viewHeight, int width,
                               int height);

    bool isOrthographic() const { return ortho_; }
    int width() const { return width_; }
    int height() const { return height_; }

    // The primary ray through pixel centre (px + 0.5, py + 0.5) given as continuous
    // coordinates sx = px + 0.5, sy = py + 0.5.
    Ray ray(double sx, double sy) const;
    // The ray of pixel (px, py): through its centre (docs/model.md §4), or through its jittered
    // sample position when jitter is on.
    Ray pixelRay(int px, int py) const {
        Vec2d s = samplePosition(px, py);
        return ray(s.x, s.y);
    }
    // Where pixel (px, py) is sampled, in continuous pixel coordinates: (px + 0.5, py + 0.5),
    // or with jitter a seeded position inside the pixel that the truth and the rasteriser
    // share (studies: breaks the aliasing between the pixel grid and periodic relief).
    Vec2d samplePosition(int px, int py) const {
        return jitter_ ? jitteredSample(px, py) : Vec2d(px + 0.5, py + 0.5);
    }
    void setJitter(bool on, uint32_t seed) { jitter_ = on, jitterSeed_ = seed; }
    bool jittered() const { return jitter_; }

    // Camera-space coordinates of a world point: (right, up, forward distance).
    Vec3d toCamera(Vec3d world) const;
    // Continuous pixel coordinates (sx, sy) of a camera-space point; for the pinhole the
    // point must be in front (forward > 0).
    Vec2d toScreen(Vec3d cam) const;

    // Unit vector from a world point toward the eye (docs/model.md §4's V before the TBN).
    Vec3d viewVector(Vec3d world) const;

    Vec3d eye() const { return eye_; }          // pinhole
    Vec3d forward() const { return forward_; }  // viewing direction
    Vec3d right() const { return right_; }
    Vec3d up() const { return up_; }
    double fovDegrees() const { return fovDegrees_; }
    double viewHeight() const { return 2 * halfHeight_; }
    Vec3d target() const { return target_; }

  private:
    Vec2d jitteredSample(int px, int py) const;
    static Camera make(bool ortho, Vec3d forward, Vec3d target, Vec3d up, double halfHeight,
                       int width, int height);
    bool ortho_ = false;
    int width_ = 0, height_ = 0;
    Vec3d eye_{0}, target_{0}, forward_{0, 0, -1}, right_{1, 0, 0}, up_{0, 1, 0};
    double fovDegrees_ = 0;
    double halfHeight_ = 1, halfWidth_ = 1;  // ortho: world units; pinhole: tan(fov/2)
    bool jitter_ = false;
    uint32_t jitterSeed_ = 0;
};

// docs/model.md §4 view direction in tangent space from view angle theta and azimuth phi
// (degrees): V = (sin t cos p, sin t sin p, cos t).
Vec3d viewFromAngles(double thetaDegrees, double phiDegrees);
// How many tiles around the central one an infinite plane needs so that every pixel ray
// of `camera` that meets the plane z = center.z meets it inside (at most `cap`).
int tilesToCover(const Camera& camera, Vec3d center, double size, int cap = 64);

}  // namespace pgt
