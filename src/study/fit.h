// `pgt fit`: for a fixed true surface (the scene's s, b), search each method's own scale,
// bias and step counts that minimise its error over a range of view angles.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace pgt {

struct FitResult {
    std::string method;           // method label in the scene
    nlohmann::json best;          // the best configuration (with its own scale and bias)
    double bestObjective = NAN;   // mean over views of the per-view objective (texels)
    double bestMean = NAN, bestP90 = NAN;
    double nativeObjective = NAN; // the same method with the truth's (s, b), as listed
    int candidates = 0;
};

struct FitReport {
    std::string objective;  // "mean" or "p90"
    std::vector<double> thetas, phis;
    std::vector<FitResult> methods;
    nlohmann::json toJson() const;
};

// Reads the scene's optional "fit" block (README "Fitting"); throws InputError on bad input.
FitReport runFit(const Scene& scene, bool progress);

}  // namespace pgt
