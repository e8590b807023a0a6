// What `pgt compare` writes (docs/outputs.md "pgt compare"): compare.csv (every cell of every
// NEW against OLD), history.csv (each configuration's error in every study, with its interval
// over seeds), compare.json (the verdict), the figures (by the front end's script) and
// compare.md, which states the test, the verdict per configuration and links the figures.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "verdict/regression.h"
#include "verdict/study_compare.h"

namespace pgt {

// A study directory as compare reads it.
struct LoadedStudy {
    std::string dir;
    nlohmann::json identity;                    // study.json
    VerdictRows rows;                           // the metric by label, case and seed
    std::map<std::string, std::string> params;  // label -> {"method", "params"} as JSON text
    std::vector<std::string> labels;            // in the order results.csv gives them
    int64_t rowCount = 0;
    bool torn = false, complete = false;
};

// Writes DIR's files (staged: all of the text files or none), the figures, then compare.md.
// `pairs[i]` and `judged[i]` are study i's against study 0 (i >= 1).
void writeCompareFiles(const std::vector<LoadedStudy>& studies,
                       const std::vector<std::vector<ConfigPair>>& pairs,
                       const std::vector<Comparison>& judged, const CompareOptions& options,
                       const CompareFigures& figures, CompareSummary& summary);

}  // namespace pgt
