// compareTruthFrames: the per-pixel UV difference of two truth frames, in texels.
#include "compare/uncertainty.h"

#include <vector>

#include "compare/statistics.h"

namespace pgt {

void UncertaintyTally::add(const Image2D<TruthSample>& coarse, const Image2D<TruthSample>& fine,
                           int texWidth, int texHeight, Address address) {
    for (size_t k = 0; k < coarse.size(); ++k) {
        const auto& a = coarse.data[k];
        const auto& b = fine.data[k];
        if (a.hit != b.hit) ++hitMismatch_;
        holesFine_ += b.hole;
        if (!(a.hit && b.hit)) continue;
        if (a.shadow != kShadowNone && b.shadow != kShadowNone)
            ++shadowCompared_, shadowMismatch_ += a.shadow != b.shadow;
        diffs_.push_back(float(uvErrorTexels(a.uv, b.uv, texWidth, texHeight, address)));
    }
}

TruthUncertainty UncertaintyTally::finish() {
    TruthUncertainty u;
    u.hitMismatch = hitMismatch_;
    u.holesFine = holesFine_;
    u.shadowMismatch = shadowMismatch_;
    u.shadowCompared = shadowCompared_;
    u.pixelsCompared = int64_t(diffs_.size());
    Summary d = summarize(diffs_);  // NaN statistics when no pixel was compared
    std::vector<float>().swap(diffs_);
    u.p50Texels = d.p50, u.p99Texels = d.p99, u.maxTexels = d.max;
    return u;
}

TruthUncertainty compareTruthFrames(const Image2D<TruthSample>& coarse,
                                    const Image2D<TruthSample>& fine, const Texture& height,
                                    Address address) {
    UncertaintyTally tally;
    tally.add(coarse, fine, height.width, height.height, address);
    return tally.finish();
}

}  // namespace pgt
