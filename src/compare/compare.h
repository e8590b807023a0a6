// Per-pixel comparison of a method's uv' with the truth UV (MODEL.md §7): error in texels,
// coverage classes, statistics and the non-finite count. Sees neither side's internals.
#pragma once

#include <cstdint>

#include "compare/statistics.h"
#include "core/image.h"
#include "core/samples.h"
#include "heightfield/texture.h"

namespace pgt {

struct CoverageCounts {
    int64_t both = 0, truthOnly = 0, rasterOnly = 0, neither = 0;
};

struct FrameStats {
    Summary error;                 // over pixels covered by both with finite uv' (texels)
    double fracAbove1Texel = NAN;  // share of those pixels with e > 1 texel
    CoverageCounts coverage;
    int64_t nonfinite = 0;                  // covered pixels whose uv' is not finite
    int64_t zeroDivide = 0, stepLimit = 0;  // stiff-case flags raised
    int64_t diverged = 0;                   // covered pixels marked by any stiff-case flag
    double fetchesMean = 0;                 // over raster-covered pixels
    uint32_t fetchesMax = 0;
};

// Compares a method image with the truth; writes the per-pixel error (NaN where not both
// covered or non-finite) to `errTexels` when given.
FrameStats compareWithTruth(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                            int texWidth, int texHeight, Address address,
                            Image2D<float>* errTexels = nullptr);

}  // namespace pgt
