// UV error in texels (docs/model.md §7) and order statistics, in double.
#pragma once

#include <cmath>
#include <vector>

#include "core/math.h"
#include "core/percentile.h"  // percentile(): the one rule
#include "heightfield/texture.h"

namespace pgt {

// e = sqrt((d.u*W)^2 + (d.v*H)^2), d = a - b, each component wrapped into [-0.5, 0.5) with
// `repeat` because the texture repeats every UV unit. NaN if either input is not finite.
inline double uvErrorTexels(Vec2d a, Vec2d b, int width, int height, Address address) {
    Vec2d d = a - b;
    if (address == Address::Repeat) d -= glm::floor(d + 0.5);
    double eu = d.x * width, ev = d.y * height;
    return std::sqrt(eu * eu + ev * ev);
}

struct Summary {
    int64_t count = 0;
    double mean = NAN, rms = NAN, p50 = NAN, p90 = NAN, p99 = NAN, max = NAN;
};
// Summary of finite values (reorders `values`). Sums in double either way; a frame's errors
// are kept in float (4 bytes a pixel, so an 8192^2 frame's fit in memory), which moves a
// percentile by at most float's rounding of one error (6e-8 of it).
Summary summarize(std::vector<double>& values);
Summary summarize(std::vector<float>& values);

}  // namespace pgt
