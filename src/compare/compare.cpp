// Error images and frame statistics (MODEL.md §7).
#include "compare/compare.h"

#include "core/error.h"
#include "methods/method.h"

namespace pgt {

FrameStats compareWithTruth(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                            int texWidth, int texHeight, Address address,
                            Image2D<float>* errTexels) {
    PGT_CHECK_EQ(truth.width, method.width);
    PGT_CHECK_EQ(truth.height, method.height);
    FrameStats fs;
    if (errTexels) *errTexels = Image2D<float>(truth.width, truth.height, NAN);
    std::vector<double> errors;
    errors.reserve(truth.size());
    double fetchSum = 0;
    int64_t covered = 0, above1 = 0;
    for (size_t k = 0; k < truth.size(); ++k) {
        const TruthSample& t = truth.data[k];
        const MethodPixel& m = method.data[k];
        if (m.covered) {
            ++covered;
            fetchSum += m.fetches;
            fs.fetchesMax = std::max(fs.fetchesMax, m.fetches);
            if (m.flags & kFlagZeroDivide) ++fs.zeroDivide;
            if (m.flags & kFlagStepLimit) ++fs.stepLimit;
            if (m.flags) ++fs.diverged;
        }
        if (t.hit && m.covered) ++fs.coverage.both;
        else if (t.hit) ++fs.coverage.truthOnly;
        else if (m.covered) ++fs.coverage.rasterOnly;
        else ++fs.coverage.neither;
        if (!m.covered) continue;
        if (!std::isfinite(m.uv.x) || !std::isfinite(m.uv.y)) {
            ++fs.nonfinite;
            continue;
        }
        if (!t.hit) continue;
        double e = uvErrorTexels(m.uv, t.uv, texWidth, texHeight, address);
        errors.push_back(e);
        above1 += e > 1.0;
        if (errTexels) errTexels->data[k] = float(e);
    }
    fs.fetchesMean = covered ? fetchSum / double(covered) : 0.0;
    fs.fracAbove1Texel = errors.empty() ? NAN : double(above1) / double(errors.size());
    fs.error = summarize(errors);
    return fs;
}

}  // namespace pgt
