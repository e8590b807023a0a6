// The checks of compare/warnings.h.
#include "compare/warnings.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "compare/statistics.h"
#include "core/format.h"

namespace pgt {

MethodChecks::Tally& MethodChecks::Tally::operator+=(const Tally& o) {
    oblique += o.oblique, unchanged += o.unchanged, alongV += o.alongV;
    tanOblique += o.tanOblique, tanCompared += o.tanCompared;
    headOn += o.headOn, headOnNonfinite += o.headOnNonfinite;
    compared += o.compared, errSum += o.errSum, noneSum += o.noneSum;
    oneView = oneView && o.oneView;
    uvMagnitude = std::max(uvMagnitude, o.uvMagnitude);
    if (o.haveOffset) {
        offMin = haveOffset ? glm::min(offMin, o.offMin) : o.offMin;
        offMax = haveOffset ? glm::max(offMax, o.offMax) : o.offMax;
        haveOffset = true;
    }
    return *this;
}

void noneErrors(const FragmentList& frags, const Image2D<TruthSample>& truth, ErrorMetric metric,
                std::vector<float>& out) {
    out.resize(frags.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, frags.size(), 4096), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            const TruthSample& t = truth.data[size_t(frags.pixel[k])];
            out[k] = t.hit ? float(uvErrorTexels(frags.uv0[k], t.uv, metric.width, metric.height,
                                                 metric.address))
                           : NAN;
        }
    });
}

void MethodChecks::add(const FragmentList& frags, const std::vector<Vec3d>& view,
                       const Image2D<MethodPixel>& pixels, const Image2D<float>& errors,
                       const std::vector<float>& noneErrors) {
    auto covered = [&](size_t k) { return pixels.data[size_t(frags.pixel[k])].covered; };
    // The frame's first V, which every other is held against.
    for (size_t k = 0; !haveView_ && k < frags.size(); ++k)
        if (covered(k)) view0_ = view[k], haveView_ = true;
    // Blocks of fragments over all cores, added up in block order (the same sums whatever the
    // cores).
    const size_t n = frags.size(), block = 4096, blocks = (n + block - 1) / block;
    std::vector<Tally> parts(blocks);
    tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
        Tally& t = parts[b];
        for (size_t k = b * block; k < std::min(n, (b + 1) * block); ++k) {
            const MethodPixel& p = pixels.data[size_t(frags.pixel[k])];
            if (!p.covered) continue;
            const Vec3d v = view[k];
            const double lateral = std::sqrt(v.x * v.x + v.y * v.y);  // V is a unit vector
            const bool finite = std::isfinite(p.uv.x) && std::isfinite(p.uv.y);
            const double tanTheta = v.z > 0 ? lateral / v.z : 0;
            // Compared where the method's error is defined (covered, finite, the truth hit).
            const float e = errors.data[size_t(frags.pixel[k])];
            if (!std::isnan(e)) {
                ++t.compared;
                t.tanCompared += tanTheta;
                t.errSum += e;
                t.noneSum += noneErrors[k];
            }
            if (lateral == 0) {
                ++t.headOn;
                t.headOnNonfinite += !finite;
            }
            const Vec3d d = v - view0_;
            t.oneView = t.oneView && glm::dot(d, d) < 1e-18;  // |v - view0| < 1e-9
            if (!finite || lateral <= 1e-3) continue;
            const Vec2d uv0 = frags.uv0[k], off = p.uv - uv0;
            ++t.oblique;
            t.tanOblique += tanTheta;
            // A method that returns uv0 gives it back rounded to float (or exactly in double).
            const double tol = 2e-7 * std::max({1.0, std::abs(uv0.x), std::abs(uv0.y)});
            t.unchanged += std::abs(off.x) <= tol && std::abs(off.y) <= tol;
            t.uvMagnitude = std::max({t.uvMagnitude, std::abs(uv0.x), std::abs(uv0.y)});
            t.alongV += (off.x * v.x + off.y * v.y) / lateral;
            t.offMin = t.haveOffset ? glm::min(t.offMin, off) : off;
            t.offMax = t.haveOffset ? glm::max(t.offMax, off) : off;
            t.haveOffset = true;
        }
    });
    for (const Tally& t : parts) all_ += t;
}

std::vector<MethodWarning> MethodChecks::finish() const {
    std::vector<MethodWarning> out;
    const bool noOffset =
        c_.displaced && !c_.skipNoOffset && all_.oblique > 0 && all_.unchanged == all_.oblique;
    if (noOffset)
        out.push_back({"no_offset", "uv' equals uv0 on all " + std::to_string(all_.oblique) +
                                        " covered pixels seen obliquely (V.xy != 0): it shows "
                                        "no parallax (a constant or wrong channel, an unused "
                                        "sampler, a zero scale, or a march that never meets "
                                        "the relief?)"});
    // The same offset on every pixel, to the float rounding of uv' = uv0 + offset (a few ulps
    // of the largest |uv|: at phi 0 or 90 one component is exact, at other azimuths neither).
    const Vec2d spread = all_.offMax - all_.offMin;
    const double rounding = 4e-7 * std::max(1.0, all_.uvMagnitude);
    if (!noOffset && !c_.skipNoOffset && c_.displaced && c_.mapVaries && all_.oneView &&
        all_.haveOffset && all_.oblique > 1 && std::max(spread.x, spread.y) <= rounding)
        out.push_back({"constant_offset",
                       "its offset is the same on all " + std::to_string(all_.oblique) +
                           " pixels of a view with one V (" + formatNumber(all_.offMin.x, 4) +
                           ", " + formatNumber(all_.offMin.y, 4) +
                           " UV) although the height map varies: it does not read the map (a "
                           "constant channel, such as .a of a height layout, or an unused "
                           "sampler?)"});
    const double meanAlong = all_.oblique > 0 ? all_.alongV / double(all_.oblique) : 0;
    if (c_.below && all_.oblique > 0 && meanAlong > 1e-6)
        out.push_back({"toward_eye", "its offsets point toward the eye (mean " +
                                         formatNumber(meanAlong, 4) +
                                         " UV along V.xy) where the relief lies below the "
                                         "polygon, which the eye ray reaches beyond uv0: check "
                                         "the sign of V"});
    // Worse than giving uv0 back, by more than a texel and a tenth, with the cause that fits
    // the data (worseThanNoneCause); at grazing views the documents' known breakdown.
    const double mean = all_.compared > 0 ? all_.errSum / double(all_.compared) : 0,
                 none = all_.compared > 0 ? all_.noneSum / double(all_.compared) : 0;
    if (c_.userCode && c_.displaced && !c_.skipNoOffset && mean > 1.1 * none + 1.0) {
        const std::string cause = worseThanNoneCause(mean);
        const std::string head = "its mean error (" + formatNumber(mean, 4) +
                                 " texels) is above no parallax's (" + formatNumber(none, 4) +
                                 ") on this view: ";
        if (cause.rfind("grazing", 0) == 0)
            out.push_back({"grazing_breakdown", head + cause});
        else
            out.push_back({"worse_than_none",
                           head + (cause.empty() ? "no cause found in its data (its (s, b) are "
                                                   "the surface's, its offsets run the relief's "
                                                   "way): the method itself"
                                                 : cause)});
    }
    if (all_.headOnNonfinite > 0)
        out.push_back({"nonfinite_head_on",
                       std::to_string(all_.headOnNonfinite) + " of " + std::to_string(all_.headOn) +
                           " pixels seen exactly head-on (V.xy = 0) have a non-finite uv' "
                           "(a division by |V.xy| or normalize(V.xy)?)"});
    return out;
}

std::string MethodChecks::worseThanNoneCause(double mean) const {
    const double h = c_.meanHeight;
    const double tanCompared = all_.compared > 0 ? all_.tanCompared / double(all_.compared) : 0;
    // An amplitude or bias other than the surface's: the offsets differ by tan theta times
    // the difference of the heights the two put at the map's mean.
    const double delta = (c_.methodScale - c_.scale) * h + (c_.methodBias - c_.bias);
    const double predicted = tanCompared * std::abs(delta) * c_.texelsPerUv;
    if (std::abs(delta) > 1e-12 && predicted >= 0.5 * mean)
        return "its (s, b) = (" + formatNumber(c_.methodScale, 4) + ", " +
               formatNumber(c_.methodBias, 4) + ") are not the surface's (" +
               formatNumber(c_.scale, 4) + ", " + formatNumber(c_.bias, 4) +
               "): the difference moves its offsets by tan theta |delta(s h + b)| = " +
               formatNumber(predicted, 4) +
               " texels (an amplitude or bias mismatch: a preset's engine cannot express this "
               "b, or its own scale is set)";
    // Offsets along V against the relief's: the mean offset parallax would make is
    // tan theta (s h + b) along V.xy.
    const double tanOblique = all_.oblique > 0 ? all_.tanOblique / double(all_.oblique) : 0;
    const double along = all_.oblique > 0 ? all_.alongV / double(all_.oblique) : 0;
    const double expected = tanOblique * (c_.methodScale * h + c_.methodBias);
    if (std::abs(expected) > 1e-12 && along * expected < 0 &&
        std::abs(along) > 0.25 * std::abs(expected))
        return "its offsets run against the relief's (mean " + formatNumber(along, 4) +
               " UV along V.xy where the relief asks " + formatNumber(expected, 4) +
               "): is the map read the wrong way round (\"texture\": \"height\" for a depth "
               "map or \"depth\" for a height map), or the scale's sign?";
    // (An orthographic view at 80 degrees has atan(mean tan) a rounding below 80.)
    const double degrees = std::atan(tanCompared) * 180.0 / kPi;
    if (degrees >= 80 - 1e-6)
        return "grazing views (mean theta " + formatNumber(degrees, 3) +
               " degrees), where parallax approximations break down (an offset grows as tan "
               "theta, a march's steps grow coarse: the documents' known limit, Welsh 2004, "
               "not a misuse)";
    return "";
}

std::string warningKinds(const std::vector<MethodWarning>& w) {
    std::string s;
    for (const MethodWarning& x : w) {
        if (!s.empty()) s += ';';
        s += x.kind;
    }
    return s;
}

}  // namespace pgt
