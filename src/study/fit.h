// `pgt fit`: for a fixed true surface (the scene's s, b), search each method's own scale and
// bias that minimise its error over a range of view angles, at each listed step count (more
// steps always help, so each count gets its own best (s, b) and the cost stays visible).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pgt {

// The best own (scale, bias) of one method at one step count (or the only one).
struct FitResult {
    std::string method;  // method label in the scene
    int steps = 0;       // the step parameter's value (0: the method has none)
    // The best configuration, its own scale and bias set where they reach the method; none
    // when every candidate gave non-finite UVs or no pixels.
    std::optional<MethodConfig> best;
    std::optional<double> scale, bias;  // the fitted values (none: s or b does not reach it)
    double bestObjective = NAN;         // mean over views of the per-view objective (texels)
    double bestMean = NAN, bestP90 = NAN;
    double nativeObjective = NAN;  // the same method with the truth's (s, b), as listed
    int candidates = 0;
    // The best as a method entry, as fit.json writes it ("scale" and "bias" only where
    // fitted, no label): a scene's methods list takes it as it is. Null when there is none.
    nlohmann::json entry() const;
};

struct FitReport {
    std::string objective;  // "mean" or "p90"
    std::string samples;    // "jittered" (one seed for every candidate) or "centre"
    uint32_t seed = 1;      // the jitter seed
    std::vector<double> thetas, phis;
    std::vector<FitResult> methods;
    std::string sceneSha1;  // the scene fitted (study/provenance.h)
    nlohmann::json toJson() const;
};

// Reads the scene's optional "fit" block (docs/studies.md "Fitting"); throws InputError on bad
// input.
FitReport runFit(const Scene& scene, bool progress);

}  // namespace pgt
