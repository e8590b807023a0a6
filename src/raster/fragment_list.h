// The rasterised fragments in compact form (one entry per covered pixel), what the method
// kernels and the GL runner consume, and a seeded subset of them for timing.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "raster/raster.h"

namespace pgt {

struct FragmentList {
    std::vector<int32_t> pixel;  // y * width + x
    std::vector<Vec2f> uv0;
    std::vector<Vec3f> view;  // unit tangent-space V, rounded to float
    std::vector<Vec2d> uv0d;  // double copies for `precision: double`
    std::vector<Vec3d> viewd;
    std::vector<Vec3f> viewExact;  // V in the exact frame of the drawn surface (meshes)
    std::vector<Vec3d> viewExactd;
    size_t size() const { return pixel.size(); }
};
FragmentList compactFragments(const Image2D<Fragment>& frags);
// A seeded random subset of at most `count` fragments (all when count <= 0 or larger).
FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed);

}  // namespace pgt
