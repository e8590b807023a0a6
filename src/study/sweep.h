// Studies (`pgt sweep`): the product of view angles, scales, biases and per-method parameter
// lists from a scene's "sweep" block, one CSV row per (case, method configuration), resumable:
// each finished case is appended and flushed, and a re-run skips the cases already there.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "study/render.h"

namespace pgt {

struct StudyCase {
    int index = 0;
    double theta = 0, phi = 0, scale = 0, bias = 0;
    double biasRatio = NAN;   // b / s when the study gave ratios
    std::string key() const;  // identity of the case in results.csv
};

struct Study {
    std::vector<StudyCase> cases;       // grouped by (scale, bias), then theta, phi
    std::vector<MethodConfig> configs;  // methods expanded by the parameter lists
    int width = 0, height = 0;
    bool jitter = false;  // pixel sample positions (README "Studies")
    TimingSpec timing;
    nlohmann::json resolved;  // what identifies the study (scene + sweep)
};

// Reads the scene's "sweep" block (README "Studies"); throws InputError on bad input.
Study parseStudy(const Scene& scene);

struct SweepOptions {
    std::string outDir;
    bool images = false;   // write each case's frame.exr, summary.json and error maps
    bool fresh = false;    // discard earlier results in outDir instead of resuming
    int maxCases = -1;     // stop after this many new cases (tests; -1 = all)
    bool progress = true;  // progress on stderr
    bool report = false;   // run analysis/report.py when every case is done (still locked)
};

// Bounds that keep a study's plan small (its lists are allocated whole).
constexpr int64_t kMaxStudyCases = 1000000;
constexpr int64_t kMaxStudyConfigs = 10000;

struct SweepSummary {
    int total = 0, resumed = 0, done = 0;
    bool finished = false;  // every case has its rows
    double wallSeconds = 0;
    std::map<std::string, double> stageMs;  // summed over the cases run: build, trace, ...
    bool reportTried = false;               // options.report and finished
    std::string reportPath, reportWhy;      // the report, or why it was not written
};

SweepSummary runSweep(const Scene& scene, const Study& study, const SweepOptions& options);

// results.csv columns, in order (README "Studies").
const std::vector<std::string>& resultColumns();

// The study directory is locked for the run (flock on DIR/.pgt-lock): a second run into the
// same directory is refused with OutputError while the first one runs.
// Runs analysis/report.py on a study directory when /usr/bin/python3 has matplotlib, pandas
// and numpy; returns the report's path, or "" with `why` set when it could not run.
std::string writeStudyReport(const std::string& outDir, std::string* why);

}  // namespace pgt
