// compareTruthFrames: the per-pixel UV difference of two truth frames, in texels.
#include "compare/uncertainty.h"

#include <vector>

#include "compare/statistics.h"

namespace pgt {

TruthUncertainty compareTruthFrames(const Image2D<TruthSample>& coarse,
                                    const Image2D<TruthSample>& fine, const Texture& height,
                                    Address address) {
    TruthUncertainty u;
    std::vector<double> diffs;
    for (size_t k = 0; k < coarse.size(); ++k) {
        const auto& a = coarse.data[k];
        const auto& b = fine.data[k];
        if (a.hit != b.hit) ++u.hitMismatch;
        if (!(a.hit && b.hit)) continue;
        diffs.push_back(uvErrorTexels(a.uv, b.uv, height.width, height.height, address));
    }
    u.pixelsCompared = int64_t(diffs.size());
    Summary d = summarize(diffs);  // NaN statistics when no pixel was compared
    u.p50Texels = d.p50, u.p99Texels = d.p99, u.maxTexels = d.max;
    return u;
}

}  // namespace pgt
