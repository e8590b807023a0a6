// The whole-frame rasteriser before binning, frozen as a test oracle (raster_reference.cpp).
#pragma once

#include "raster/raster.h"

namespace pgt::reference {

Image2D<Fragment> rasterize(const BaseMesh& mesh, const Camera& camera,
                            const RasterOptions& options, RasterStats* stats = nullptr);

}  // namespace pgt::reference
