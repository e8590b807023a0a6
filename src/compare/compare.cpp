// Error images and frame statistics (MODEL.md §7).
#include "compare/compare.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "methods/method.h"

namespace pgt {

namespace {
// Per-pixel tallies of one block of the frame (summed over blocks).
struct Tally {
    double fetchSum = 0;
    int64_t covered = 0, above1 = 0, nonfinite = 0, zeroDivide = 0, stepLimit = 0, diverged = 0;
    int64_t both = 0, truthOnly = 0, rasterOnly = 0, neither = 0;
    uint32_t fetchesMax = 0;
    Tally& operator+=(const Tally& o) {
        fetchSum += o.fetchSum;
        covered += o.covered, above1 += o.above1, nonfinite += o.nonfinite;
        zeroDivide += o.zeroDivide, stepLimit += o.stepLimit, diverged += o.diverged;
        both += o.both, truthOnly += o.truthOnly, rasterOnly += o.rasterOnly, neither += o.neither;
        fetchesMax = std::max(fetchesMax, o.fetchesMax);
        return *this;
    }
};

// Counts one pixel into `acc`; returns its UV error in texels, NaN where none is defined
// (the method did not cover it, its uv' is not finite, or the truth missed).
double tallyPixel(Tally& acc, const TruthSample& t, const MethodPixel& m, int texWidth,
                  int texHeight, Address address) {
    if (m.covered) {
        ++acc.covered;
        acc.fetchSum += m.fetches;
        acc.fetchesMax = std::max(acc.fetchesMax, m.fetches);
        if (m.flags & kFlagZeroDivide) ++acc.zeroDivide;
        if (m.flags & kFlagStepLimit) ++acc.stepLimit;
        if (m.flags) ++acc.diverged;
    }
    if (t.hit && m.covered)
        ++acc.both;
    else if (t.hit)
        ++acc.truthOnly;
    else if (m.covered)
        ++acc.rasterOnly;
    else
        ++acc.neither;
    if (!m.covered) return NAN;
    if (!std::isfinite(m.uv.x) || !std::isfinite(m.uv.y)) {
        ++acc.nonfinite;
        return NAN;
    }
    if (!t.hit) return NAN;
    double e = uvErrorTexels(m.uv, t.uv, texWidth, texHeight, address);
    acc.above1 += e > 1.0;
    return e;
}

FrameStats frameStats(const Tally& all, std::vector<double>& errors) {
    FrameStats fs;
    fs.fetchesMax = all.fetchesMax;
    fs.zeroDivide = all.zeroDivide;
    fs.stepLimit = all.stepLimit;
    fs.diverged = all.diverged;
    fs.nonfinite = all.nonfinite;
    fs.coverage.both = all.both;
    fs.coverage.truthOnly = all.truthOnly;
    fs.coverage.rasterOnly = all.rasterOnly;
    fs.coverage.neither = all.neither;
    fs.fetchesMean = all.covered ? all.fetchSum / double(all.covered) : 0.0;
    fs.fracAbove1Texel = errors.empty() ? NAN : double(all.above1) / double(errors.size());
    fs.error = summarize(errors);
    return fs;
}

}  // namespace

FrameStats compareWithTruth(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                            int texWidth, int texHeight, Address address,
                            Image2D<float>* errTexels) {
    PGT_CHECK_EQ(truth.width, method.width);
    PGT_CHECK_EQ(truth.height, method.height);
    if (errTexels) *errTexels = Image2D<float>(truth.width, truth.height, NAN);
    // Pixels in blocks over all cores; an error slot stays NaN where no error is defined.
    std::vector<double> perPixel(truth.size(), NAN);
    Tally all = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, truth.size(), 4096), Tally{},
        [&](const tbb::blocked_range<size_t>& r, Tally acc) {
            for (size_t k = r.begin(); k < r.end(); ++k) {
                double e =
                    tallyPixel(acc, truth.data[k], method.data[k], texWidth, texHeight, address);
                perPixel[k] = e;
                if (errTexels && !std::isnan(e)) errTexels->data[k] = float(e);
            }
            return acc;
        },
        [](Tally x, const Tally& y) { return x += y; });
    std::vector<double> errors;
    errors.reserve(size_t(all.both));
    for (double e : perPixel)
        if (!std::isnan(e)) errors.push_back(e);
    return frameStats(all, errors);
}

}  // namespace pgt
