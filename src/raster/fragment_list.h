// The rasterised fragments in compact form (one entry per covered pixel), what the method
// kernels and the GL runner consume, and a seeded subset of them for timing.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "raster/raster.h"

namespace pgt {

// In double, as the rasteriser made them: a float method (and the GL) rounds uv0 and V to
// float when it reads them, exactly once, as a GPU's varyings are; `precision: double`
// reads them as they are. 68 bytes per fragment.
struct FragmentList {
    std::vector<int32_t> pixel;  // y * width + x
    std::vector<Vec2d> uv0;
    std::vector<Vec3d> view;       // unit tangent-space V (003 Listing 7.8's frame)
    std::vector<Vec3d> viewExact;  // V in the exact frame of the drawn surface (meshes)
    size_t size() const { return pixel.size(); }
};
FragmentList compactFragments(const Image2D<Fragment>& frags);
// A seeded random subset of at most `count` fragments (all when count <= 0 or larger).
FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed);

}  // namespace pgt
