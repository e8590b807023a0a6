// The truth's own uncertainty (docs/model.md §5): the same view traced at the truth's rate and at
// twice that rate, compared pixel by pixel like a method against the truth.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/samples.h"
#include "heightfield/texture.h"

namespace pgt {

// The truth's own uncertainty (docs/model.md §5): the same frame at two rates.
struct TruthUncertainty {
    int rate = 0, rateFine = 0;
    int64_t pixelsCompared = 0;  // hit in both frames
    int64_t hitMismatch = 0;     // hit in one frame only (silhouette and border pixels)
    int64_t holesFine = 0;       // the finer frame's holes (TruthSample::hole)
    // With a light: pixels hit in both whose shadow differs between the rates (docs/model.md
    // §5b), of `shadowCompared`; shadow disagreements below their share are the truth's own.
    int64_t shadowMismatch = 0, shadowCompared = 0;
    // NaN when no pixel was compared: nothing was measured (written as null / nan).
    double p50Texels = NAN, p99Texels = NAN, maxTexels = NAN;
};

// The two frames compared band by band: the counts, and the differences kept in float.
class UncertaintyTally {
  public:
    void add(const Image2D<TruthSample>& coarse, const Image2D<TruthSample>& fine, int texWidth,
             int texHeight, Address address);
    TruthUncertainty finish();  // reorders the kept differences

  private:
    int64_t hitMismatch_ = 0, holesFine_ = 0, shadowMismatch_ = 0, shadowCompared_ = 0;
    std::vector<float> diffs_;
};

TruthUncertainty compareTruthFrames(const Image2D<TruthSample>& coarse,
                                    const Image2D<TruthSample>& fine, const Texture& height,
                                    Address address);

}  // namespace pgt
