// Studies (`pgt sweep`): a study plan (study/plan.h) run case by case into results.csv, one
// row per (case, method configuration), resumable: each finished case is appended and
// flushed, and a re-run skips the cases already there.
#pragma once

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/clock.h"
#include "frame/render.h"
#include "scene/scene.h"
#include "study/plan.h"
#include "study/result_columns.h"  // results.csv's columns

namespace pgt {

struct SweepOptions {
    std::string outDir;
    bool images = false;   // write each case's frame.exr, summary.json and error maps
    bool fresh = false;    // discard earlier results in outDir instead of resuming
    int maxCases = -1;     // stop after this many new cases (tests; -1 = all)
    bool progress = true;  // progress on stderr
    // Writes the study's report when every case is done (still under the lock): returns its
    // path, or "" with the reason set. Given by the front end (cli/report.h); none: no report.
    std::function<std::string(const std::string& outDir, std::string* why)> report = {};
    // This run's share of the study (--shard I/N): the cases whose index is I modulo N, so
    // every shard gets every (s, b) and view angle alike. study.json then names the shard.
    int shardIndex = 0, shardCount = 1;
};

// The study identity a shard's study.json holds: `resolved` plus
// {"shard": {"index", "count", "cases", "labels"}}.
nlohmann::json shardIdentity(const Study& study, int index, int count);

struct SweepSummary {
    int total = 0, resumed = 0, done = 0;
    bool finished = false;  // every case has its rows
    double wallSeconds = 0;
    StageTimes stageMs;                 // summed over the cases run: build, trace, ...
    bool reportTried = false;           // options.report and finished
    std::string reportPath, reportWhy;  // the report, or why it was not written
};

SweepSummary runSweep(const Scene& scene, const Study& study, const SweepOptions& options);

}  // namespace pgt
