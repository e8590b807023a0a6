#!/usr/bin/env bash
# A pgt study on a Slurm cluster: a job array of N shards (pgt sweep --shard slurm:N), then a
# merge job that runs only when every shard succeeded (--dependency=afterok) and writes the
# whole study, with its report, to OUT/study. Prints the two job ids.
#
#   analysis/slurm/submit_study.sh SCENE OUT N [PGT] [-- extra sbatch options...]
#
# OUT must be on a file system every node sees. A shard that fails or is killed can be
# resubmitted on its own (sbatch --array=I ...): it resumes where it stopped.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 SCENE OUT N [PGT] [-- sbatch options...]" >&2
  exit 2
fi
scene=$(realpath "$1"); out=$(realpath -m "$2"); n=$3; shift 3
pgt=$(command -v pgt || true)
if [ $# -gt 0 ] && [ "$1" != "--" ]; then pgt=$(realpath "$1"); shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
if [ -z "$pgt" ]; then echo "$0: pgt not found (give its path)" >&2; exit 2; fi
case $n in ''|*[!0-9]*|0) echo "$0: N must be a positive integer, not '$n'" >&2; exit 2;; esac
mkdir -p "$out/logs"
q() { printf '%q' "$1"; }
array=$(sbatch --parsable "$@" --job-name=pgt-shards --array="0-$((n - 1))" \
  --output="$out/logs/shard_%a.log" \
  --wrap="$(q "$pgt") sweep $(q "$scene") --out $(q "$out")/shard_\$SLURM_ARRAY_TASK_ID --no-report --shard slurm:$n")
array=${array%%;*}
shards=""
for ((i = 0; i < n; i++)); do shards+=" $(q "$out/shard_$i")"; done
merge=$(sbatch --parsable "$@" --job-name=pgt-merge --dependency="afterok:$array" \
  --output="$out/logs/merge.log" --wrap="$(q "$pgt") merge$shards --out $(q "$out")/study")
merge=${merge%%;*}
echo "shards: job $array (array 0-$((n - 1))), merge: job $merge -> $out/study"
