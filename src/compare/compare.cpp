// Error images and frame statistics (docs/model.md §7).
#include "compare/compare.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "methods/method.h"

namespace pgt {

ShadowCounts& ShadowCounts::operator+=(const ShadowCounts& o) {
    compared += o.compared, differ += o.differ;
    right += o.right, differRight += o.differRight;
    wrong += o.wrong, differWrong += o.differWrong;
    truthDark += o.truthDark, methodDark += o.methodDark;
    return *this;
}

CompareTally& CompareTally::operator+=(const CompareTally& o) {
    fetchSum += o.fetchSum;
    depthSignedSum += o.depthSignedSum;
    shadow += o.shadow;
    covered += o.covered, above1 += o.above1, nonfinite += o.nonfinite;
    zeroDivide += o.zeroDivide, stepLimit += o.stepLimit, diverged += o.diverged;
    both += o.both, truthOnly += o.truthOnly, rasterOnly += o.rasterOnly, neither += o.neither;
    fetchesMax = std::max(fetchesMax, o.fetchesMax);
    return *this;
}

namespace {

// Counts one pixel into `acc`; returns its UV error in texels, NaN where none is defined
// (the method did not cover it, its uv' is not finite, or the truth missed).
double tallyPixel(CompareTally& acc, const TruthSample& t, const MethodPixel& m, int texWidth,
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
    if (t.shadow != kShadowNone && m.shadow != kShadowNone) {
        ShadowCounts& sc = acc.shadow;
        const bool differ = t.shadow != m.shadow;
        ++sc.compared;
        sc.differ += differ;
        sc.truthDark += t.shadow == kShadowDark;
        sc.methodDark += m.shadow == kShadowDark;
        if (e <= 1.0)
            ++sc.right, sc.differRight += differ;
        else
            ++sc.wrong, sc.differWrong += differ;
    }
    return e;
}

// A compared pixel's depth error in texels (docs/model.md §7b), signed (> 0: too deep); NaN
// where either depth is not finite.
double depthErrorTexels(const TruthSample& t, const MethodPixel& m, int texWidth, int texHeight) {
    return (double(m.depth) - t.depth) * std::sqrt(double(texWidth) * double(texHeight));
}

FrameStats frameStats(const CompareTally& all, std::vector<float>& errors) {
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
    fs.shadow = all.shadow;
    return fs;
}

}  // namespace

float codedError(const TruthSample& t, const MethodPixel& m, double e) {
    if (m.covered && (!std::isfinite(m.uv.x) || !std::isfinite(m.uv.y))) return kCodeNonFinite;
    if (m.covered && t.hit) return float(e);
    return t.hit ? kCodeTruthOnly : m.covered ? kCodeRasterOnly : kCodeNeither;
}

void ErrorTally::add(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                     int texWidth, int texHeight, Address address, Image2D<float>* errTexels,
                     int y0) {
    PGT_CHECK_EQ(truth.width, method.width);
    PGT_CHECK_EQ(truth.height, method.height);
    if (errTexels && (errTexels->width != truth.width || errTexels->height != truth.height))
        *errTexels = Image2D<float>(truth.width, truth.height);
    float* coded = nullptr;
    if (inPlace_) {
        PGT_CHECK(truth.width == coded_.width && y0 >= 0 && y0 + truth.height <= coded_.height);
        coded = &coded_.at(0, y0);
    }
    // Pixels in blocks over all cores, each block's errors in pixel order at the block's own
    // offset of a scratch buffer (kept from band to band); the blocks' runs are joined in
    // order, so the kept errors do not depend on the threads.
    const size_t n = truth.size(), block = 4096, blocks = (n + block - 1) / block;
    foundScratch_.resize(inPlace_ ? 0 : n);
    depthScratch_.resize(n);
    std::vector<uint32_t> found(blocks, 0), depths(blocks, 0);
    // Each block's signed depth sum apart, added in block order below: a sum joined in the
    // reduction's order would differ from run to run in its last digits.
    std::vector<double> depthSums(blocks, 0.0);
    all_ += tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, blocks), CompareTally{},
        [&](const tbb::blocked_range<size_t>& r, CompareTally acc) {
            for (size_t b = r.begin(); b < r.end(); ++b)
                for (size_t k = b * block; k < std::min(n, (b + 1) * block); ++k) {
                    double e = tallyPixel(acc, truth.data[k], method.data[k], texWidth, texHeight,
                                          address);
                    if (errTexels) errTexels->data[k] = float(e);
                    if (!std::isnan(e)) {
                        const double d =
                            depthErrorTexels(truth.data[k], method.data[k], texWidth, texHeight);
                        if (std::isfinite(d)) {
                            depthSums[b] += d;
                            depthScratch_[b * block + depths[b]++] = float(std::fabs(d));
                        }
                    }
                    if (coded)
                        coded[k] = codedError(truth.data[k], method.data[k], e);
                    else if (!std::isnan(e))
                        foundScratch_[b * block + found[b]++] = float(e);
                }
            return acc;
        },
        [](CompareTally x, const CompareTally& y) { return x += y; });
    for (size_t b = 0; b < blocks; ++b) {
        all_.depthSignedSum += depthSums[b];
        const auto at = [&](std::vector<float>& v) { return v.begin() + int64_t(b * block); };
        if (!inPlace_)
            errors_.insert(errors_.end(), at(foundScratch_), at(foundScratch_) + found[b]);
        depthErrors_.insert(depthErrors_.end(), at(depthScratch_), at(depthScratch_) + depths[b]);
    }
}

namespace {
void addDepths(FrameStats& fs, const CompareTally& all, std::vector<float>& depthErrors) {
    fs.depthError = summarize(depthErrors);
    fs.depthSignedMean =
        depthErrors.empty() ? NAN : all.depthSignedSum / double(depthErrors.size());
    std::vector<float>().swap(depthErrors);
}
}  // namespace

FrameStats ErrorTally::finish() {
    if (!inPlace_) {
        FrameStats fs = frameStats(all_, errors_);
        std::vector<float>().swap(errors_);
        addDepths(fs, all_, depthErrors_);
        return fs;
    }
    std::vector<float> errors;  // the errors (codes >= 0) in pixel order
    errors.reserve(size_t(all_.both));
    for (float c : coded_.data)
        if (c >= 0) errors.push_back(c);
    FrameStats fs = frameStats(all_, errors);
    addDepths(fs, all_, depthErrors_);
    return fs;
}

FrameStats compareWithTruth(const Image2D<TruthSample>& truth, const Image2D<MethodPixel>& method,
                            int texWidth, int texHeight, Address address,
                            Image2D<float>* errTexels) {
    ErrorTally tally;
    tally.add(truth, method, texWidth, texHeight, address, errTexels);
    return tally.finish();
}

}  // namespace pgt
