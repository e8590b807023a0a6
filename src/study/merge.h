// `pgt merge`: the shards of one study (`pgt sweep --shard I/N`, each a resumable study
// directory) joined into one study directory, as if the study had run on one machine.
#pragma once

#include <string>
#include <vector>

namespace pgt {

struct MergeSummary {
    int shards = 0, cases = 0, rows = 0;
};

// Checks that every DIR holds a shard of the same study (study.json equal but for its
// shard), that no shard is torn (a case with only some of its rows, a cut last line) and
// that together they hold every case; otherwise InputError naming the directory, or the
// missing case indices. Writes OUT/study.json (the study's, without the shard) and
// OUT/results.csv (every row, in case order, as an unsharded run writes them).
MergeSummary mergeShards(const std::vector<std::string>& dirs, const std::string& outDir);

}  // namespace pgt
