// --shard of `pgt sweep`: which shard of a study this run writes (docs/studies.md "One study
// on several machines"), given as I/N or taken from a Slurm job array.
#pragma once

#include <string>

#include "study/sweep.h"

namespace pgt {

// "I/N": shard I of N. "slurm:N" or "slurm" inside a Slurm job array: I is the array index
// (SLURM_ARRAY_TASK_ID; `sbatch --array=1` of a failed task reruns shard 1); N is the N
// given, else the shard count of the study already in `outDir` (a resubmitted task resumes
// its shard), else SLURM_ARRAY_TASK_COUNT when the array is the plain range 0..N-1 (a
// stepped or partial array does not tell N: InputError asking for slurm:N). Sets
// options.shardIndex and shardCount; InputError naming --shard or the variable.
void parseShard(const std::string& value, const std::string& outDir, SweepOptions& options);

}  // namespace pgt
