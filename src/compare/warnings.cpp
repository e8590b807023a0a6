// The checks of compare/warnings.h.
#include "compare/warnings.h"

#include <algorithm>
#include <cmath>

#include "compare/statistics.h"
#include "core/format.h"

namespace pgt {

void MethodChecks::add(const FragmentList& frags, const std::vector<Vec3d>& view,
                       const Image2D<MethodPixel>& pixels, const Image2D<TruthSample>* truth,
                       ErrorMetric metric) {
    for (size_t k = 0; k < frags.size(); ++k) {
        const MethodPixel& p = pixels.data[size_t(frags.pixel[k])];
        if (!p.covered) continue;
        const Vec3d v = view[k];
        const double lateral = std::hypot(v.x, v.y);
        const bool finite = std::isfinite(p.uv.x) && std::isfinite(p.uv.y);
        if (truth && finite && truth->data[size_t(frags.pixel[k])].hit) {
            const Vec2d t = truth->data[size_t(frags.pixel[k])].uv;
            ++compared_;
            errSum_ += uvErrorTexels(p.uv, t, metric.width, metric.height, metric.address);
            noneSum_ += uvErrorTexels(frags.uv0[k], t, metric.width, metric.height, metric.address);
        }
        if (lateral == 0) {
            ++headOn_;
            headOnNonfinite_ += !finite;
        }
        if (!haveView_) view0_ = v, haveView_ = true;
        oneView_ = oneView_ && glm::length(v - view0_) < 1e-9;
        if (!finite || lateral <= 1e-3) continue;
        const Vec2d uv0 = frags.uv0[k], off = p.uv - uv0;
        ++oblique_;
        // A method that returns uv0 gives it back rounded to float (or exactly in double).
        const double tol = 2e-7 * std::max({1.0, std::abs(uv0.x), std::abs(uv0.y)});
        unchanged_ += std::abs(off.x) <= tol && std::abs(off.y) <= tol;
        alongV_ += (off.x * v.x + off.y * v.y) / lateral;
        offMin_ = haveOffset_ ? glm::min(offMin_, off) : off;
        offMax_ = haveOffset_ ? glm::max(offMax_, off) : off;
        haveOffset_ = true;
    }
}

std::vector<MethodWarning> MethodChecks::finish() const {
    std::vector<MethodWarning> out;
    const bool noOffset =
        c_.displaced && !c_.skipNoOffset && oblique_ > 0 && unchanged_ == oblique_;
    if (noOffset)
        out.push_back({"no_offset", "uv' equals uv0 on all " + std::to_string(oblique_) +
                                        " covered pixels seen obliquely (V.xy != 0): it shows "
                                        "no parallax (a constant or wrong channel, an unused "
                                        "sampler, a zero scale, or a march that never meets "
                                        "the relief?)"});
    const Vec2d spread = offMax_ - offMin_;
    if (!noOffset && !c_.skipNoOffset && c_.displaced && c_.mapVaries && oneView_ && haveOffset_ &&
        oblique_ > 1 && std::max(spread.x, spread.y) <= 1e-7)
        out.push_back({"constant_offset",
                       "its offset is the same on all " + std::to_string(oblique_) +
                           " pixels of a view with one V (" + formatNumber(offMin_.x, 4) + ", " +
                           formatNumber(offMin_.y, 4) +
                           " UV) although the height map varies: it does not read the map (a "
                           "constant channel, such as .a of a height layout, or an unused "
                           "sampler?)"});
    const double meanAlong = oblique_ > 0 ? alongV_ / double(oblique_) : 0;
    if (c_.below && oblique_ > 0 && meanAlong > 1e-6)
        out.push_back({"toward_eye", "its offsets point toward the eye (mean " +
                                         formatNumber(meanAlong, 4) +
                                         " UV along V.xy) where the relief lies below the "
                                         "polygon, which the eye ray reaches beyond uv0: check "
                                         "the sign of V"});
    // Worse than giving uv0 back, by more than a texel and a tenth: the offsets run the wrong
    // way (a depth map read as a height map or the reverse, a scale of the wrong sign).
    const double mean = compared_ > 0 ? errSum_ / double(compared_) : 0,
                 none = compared_ > 0 ? noneSum_ / double(compared_) : 0;
    if (c_.userCode && c_.displaced && !c_.skipNoOffset && mean > 1.1 * none + 1.0)
        out.push_back({"worse_than_none",
                       "its mean error (" + formatNumber(mean, 4) +
                           " texels) is above no parallax's (" + formatNumber(none, 4) +
                           ") on this view: is the map read the wrong way round (\"texture\": "
                           "\"height\" for a depth map or \"depth\" for a height map), or the "
                           "scale's sign?"});
    if (headOnNonfinite_ > 0)
        out.push_back({"nonfinite_head_on",
                       std::to_string(headOnNonfinite_) + " of " + std::to_string(headOn_) +
                           " pixels seen exactly head-on (V.xy = 0) have a non-finite uv' "
                           "(a division by |V.xy| or normalize(V.xy)?)"});
    return out;
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
