// Per-pixel comparison of a method's uv' with the truth UV (docs/model.md §7): error in texels,
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

// Shadow states against the truth's (docs/model.md §7b), over the compared pixels where both
// the truth and the method have one; split by whether the method's uv' is right (e <= 1
// texel) or wrong.
struct ShadowCounts {
    int64_t compared = 0, differ = 0;
    int64_t right = 0, differRight = 0;  // e <= 1 texel
    int64_t wrong = 0, differWrong = 0;  // e > 1 texel
    int64_t truthDark = 0, methodDark = 0;
    ShadowCounts& operator+=(const ShadowCounts& o);
};

struct FrameStats {
    Summary error;  // over pixels covered by both with finite uv' (texels)
    // |depth' - depth_true| (docs/model.md §7b) in texels (UV units x sqrt(W H)), over the
    // compared pixels where both depths are finite; its signed mean (> 0: the method puts the
    // surface too deep).
    Summary depthError;
    double depthSignedMean = NAN;
    ShadowCounts shadow;
    double fracAbove1Texel = NAN;  // share of those pixels with e > 1 texel
    CoverageCounts coverage;
    int64_t nonfinite = 0;                  // covered pixels whose uv' is not finite
    int64_t zeroDivide = 0, stepLimit = 0;  // stiff-case flags raised
    int64_t diverged = 0;                   // covered pixels marked by any stiff-case flag
    double fetchesMean = 0;                 // over raster-covered pixels
    uint32_t fetchesMax = 0;
};

// Per-pixel counts of a method against the truth, summed over pixels and bands.
struct CompareTally {
    double fetchSum = 0;
    int64_t covered = 0, above1 = 0, nonfinite = 0, zeroDivide = 0, stepLimit = 0, diverged = 0;
    int64_t both = 0, truthOnly = 0, rasterOnly = 0, neither = 0;
    uint32_t fetchesMax = 0;
    double depthSignedSum = 0;
    ShadowCounts shadow;
    CompareTally& operator+=(const CompareTally& o);
};

// A pixel's comparison in one float: its error in texels (>= 0), or the negative code of
// why it has none.
constexpr float kCodeTruthOnly = -1;   // truth hit, the method did not cover the pixel
constexpr float kCodeRasterOnly = -2;  // covered, the truth ray missed the sheet
constexpr float kCodeNonFinite = -3;   // covered, uv' not finite
constexpr float kCodeNeither = -4;
float codedError(const TruthSample& truth, const MethodPixel& method, double errTexels);

// A frame compared band by band (rows in any grouping): the counts, and every compared
// pixel's error kept in float for the percentiles. Constructed with the frame's size, it
// keeps them in place instead: the whole frame's coded errors (codedError), which the error
// maps are drawn from, at 4 bytes a pixel whatever the coverage.
class ErrorTally {
  public:
    ErrorTally() = default;
    ErrorTally(int width, int height) : coded_(width, height, kCodeNeither), inPlace_(true) {}
    // One band: the truth and the method image of the same pixels. `errTexels` (optional)
    // gets each pixel's error, NaN where none is defined (not both covered, or non-finite).
    // `y0`: the band's first row in the frame (in-place tallies).
    void add(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method, int texWidth,
             int texHeight, Address address, Image2D<float>* errTexels = nullptr, int y0 = 0);
    // The statistics of every band added (reorders the kept errors; in place, sorts a copy).
    FrameStats finish();
    // In place: the frame's coded errors (moved out).
    Image2D<float> takeCoded() { return std::move(coded_); }

  private:
    CompareTally all_;
    std::vector<float> errors_;
    std::vector<float> depthErrors_;  // |depth' - depth_true| in texels, pixel order
    Image2D<float> coded_;
    bool inPlace_ = false;
    std::vector<float> foundScratch_, depthScratch_;  // a band's, block by block (add)
};

// Compares a method image with the truth (one band: the whole frame); writes the per-pixel
// error (NaN where not both covered or non-finite) to `errTexels` when given.
FrameStats compareWithTruth(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                            int texWidth, int texHeight, Address address,
                            Image2D<float>* errTexels = nullptr);

}  // namespace pgt
