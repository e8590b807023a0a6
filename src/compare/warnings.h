// Silent mistakes a method's output shows on one frame (docs/outputs.md "Warnings"): a
// shader that gives uv0 back everywhere, one whose offset does not depend on the map, one
// whose offsets point toward the eye where the relief lies below the polygon (the sign of V),
// one whose error is above no parallax's (uv0's) on the frame (a height read as a depth or the
// reverse), and non-finite uv' at an exactly head-on view. Warnings never fail a run: they go to
// stderr, summary.json and results.csv beside the statistics.
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "core/samples.h"
#include "heightfield/texture.h"
#include "raster/fragment_list.h"

namespace pgt {

struct MethodWarning {
    // "no_offset", "constant_offset", "toward_eye", "worse_than_none", "nonfinite_head_on",
    // "grazing_breakdown"
    std::string kind;
    std::string text;  // one line, without the method's label
};

// What a frame says of the case it is checked against.
struct CheckContext {
    bool displaced = false;     // the (s, b) the method is given moves the surface
    bool below = false;         // the true relief lies under the polygon: s h + b <= 0 for all h
    bool mapVaries = false;     // the height map is not constant
    bool skipNoOffset = false;  // "none": gives uv0 back by definition (no offset checks)
    bool userCode = false;      // a shader or preset (worse_than_none is asked of these)
    // What worse_than_none's causes are tested with: the truth's (s, b), the method's, the
    // map's mean height and texels per UV unit (docs/outputs.md "Warnings").
    double scale = 0, bias = 0, methodScale = 0, methodBias = 0;
    double meanHeight = 0.5, texelsPerUv = 1;
};

// The map a band's errors are measured on (compare/statistics.h uvErrorTexels).
struct ErrorMetric {
    int width = 1, height = 1;
    Address address = Address::Repeat;
};

// Fed band by band with the fragments and the method's pixels (V as the method got it).
class MethodChecks {
  public:
    explicit MethodChecks(CheckContext c = {}) : c_(c) {}
    // For the comparison with no parallax: `errors`, the method's error in texels at each
    // pixel of the band (ErrorTally::add's; NaN where none is defined), and `noneErrors`,
    // uv0's against the truth at each fragment (noneErrors()).
    void add(const FragmentList& frags, const std::vector<Vec3d>& view,
             const Image2D<MethodPixel>& pixels, const Image2D<float>& errors,
             const std::vector<float>& noneErrors);
    std::vector<MethodWarning> finish() const;
    // Why the mean error is above no parallax's, tested on the data in this order: an (s, b)
    // other than the surface's whose offset difference tan theta |delta(s h + b)| accounts
    // for at least half the error; offsets along V of the opposite sign to the relief's (an
    // inverted map or scale); a grazing view (mean theta >= 80 degrees), where parallax
    // approximations break down as the documents say. Empty: none fits.
    std::string worseThanNoneCause(double mean) const;

  private:
    // What the fragments of a band (or of a block of it) add up to.
    struct Tally {
        int64_t oblique = 0;    // covered, finite, |V.xy| > 1e-3
        int64_t unchanged = 0;  // of those, uv' = uv0 (to float rounding)
        double alongV = 0;      // sum of (uv' - uv0) . V.xy / |V.xy| over them
        double tanOblique = 0;  // sum of tan theta over them
        int64_t headOn = 0, headOnNonfinite = 0;
        int64_t compared = 0;            // finite uv', truth hit
        double errSum = 0, noneSum = 0;  // their errors in texels, the method's and uv0's
        double tanCompared = 0;          // their tan theta summed
        bool oneView = true;             // every V within 1e-9 of the frame's first
        bool haveOffset = false;
        Vec2d offMin{0}, offMax{0};
        double uvMagnitude = 0;  // the largest |uv0| component of the oblique pixels
        Tally& operator+=(const Tally& o);
    };
    CheckContext c_;
    Tally all_;
    bool haveView_ = false;
    Vec3d view0_{0};
};

// uv0's error in texels against the truth at each fragment of a band (NaN where the truth
// missed): what every method's checks compare theirs with, made once a band.
void noneErrors(const FragmentList& frags, const Image2D<TruthSample>& truth, ErrorMetric metric,
                std::vector<float>& out);

// "no_offset;toward_eye": the kinds as results.csv's `warnings` column holds them.
std::string warningKinds(const std::vector<MethodWarning>& w);

}  // namespace pgt
