// `pgt merge`: the shards of one study (`pgt sweep --shard I/N`, each a resumable study
// directory) joined into one study directory, as if the study had run on one machine.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace pgt {

struct MergeSummary {
    int shards = 0, cases = 0, rows = 0;
    std::string reportPath, reportWhy;  // the report, or why it was not written
};

// Writes a study directory's report (cli/report.h): its path, or "" with the reason set.
using ReportWriter = std::function<std::string(const std::string& outDir, std::string* why)>;

// Checks that every DIR holds a shard of the same study (study.json equal but for its
// shard block, which is read strictly), that every row is the study's (its case index a shard
// case, its angles, scale and bias the plan's for that case, its label a configuration of the
// study with that method and parameters, once per case), that no shard is torn (a case with
// only some of its rows, a cut last line) and that together they hold every case; otherwise
// InputError naming the directory or the results.csv line and field, or the missing case
// indices. The memory it needs is checked against the limit before anything is read. Then,
// under OUT's study lock (OutputError while a sweep or merge holds it), and only when OUT is
// none of the shards and holds no other study (InputError), writes OUT/study.json (the
// study's, without the shard) and OUT/results.csv (every row, in case order, as an unsharded
// run writes them), and the report when `report` is given.
MergeSummary mergeShards(const std::vector<std::string>& dirs, const std::string& outDir,
                         const ReportWriter& report = {});

}  // namespace pgt
