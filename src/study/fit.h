// `pgt fit`: for a fixed true surface (the scene's s, b), search each method's own scale and
// bias that minimise its error over a range of view angles, at each listed step count (more
// steps always help, so each count gets its own best (s, b) and the cost stays visible).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pgt {

// The best own (scale, bias) of one method at one step count (or the only one).
struct FitResult {
    std::string method;          // method label in the scene
    int steps = 0;               // the step parameter's value (0: the method has none)
    nlohmann::json best;         // the best configuration (with its own scale and bias)
    double bestObjective = NAN;  // mean over views of the per-view objective (texels)
    double bestMean = NAN, bestP90 = NAN;
    double nativeObjective = NAN;  // the same method with the truth's (s, b), as listed
    int candidates = 0;
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
