// A study's plan: the product of view angles, scales and biases from a scene's "sweep"
// block (the cases) and the method configurations its per-method parameter lists make, as
// values; what identifies the study. Run by study/sweep.h.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluate/evaluate.h"
#include "methods/method.h"
#include "scene/scene.h"

namespace pgt {

struct StudyCase {
    int index = 0;
    double theta = 0, phi = 0, scale = 0, bias = 0;
    double biasRatio = NAN;                   // b / s when the study gave ratios
    double lightTheta = NAN, lightPhi = NAN;  // the light's angles; NaN: the scene has none
    double seed = 1;          // the pixels' jitter seed: one replicate of the case (an integer)
    std::string key() const;  // identity of the case in results.csv
};

struct Study {
    std::vector<StudyCase> cases;       // grouped by (scale, bias), then theta, phi, seed
    std::vector<MethodConfig> configs;  // methods expanded by the parameter lists
    int width = 0, height = 0;
    bool jitter = false;  // pixel sample positions (docs/studies.md)
    TimingSpec timing;
    nlohmann::json resolved;  // what identifies the study (scene + sweep)
};

// Reads the scene's "sweep" block (docs/studies.md); throws InputError on bad input.
Study parseStudy(const Scene& scene);

// The cases of the study a study.json identifies (its "sweep" and resolved "scene"), made as
// parseStudy makes them: what pgt merge checks every shard's rows against. InputError naming
// `file` when the identity is not a study's.
std::vector<StudyCase> planCases(const nlohmann::json& identity, const std::string& file);

// Bounds that keep a study's plan small (its lists are allocated whole).
constexpr int64_t kMaxStudyCases = 1000000;
constexpr int64_t kMaxStudyConfigs = 10000;

}  // namespace pgt
