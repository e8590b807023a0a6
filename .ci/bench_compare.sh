#!/usr/bin/env bash
# The change's benchmarks against its parent's, on this machine, in one run (docs/performance.md
# "A frame's stages against their floors"): the parent commit's pgt_bench is built in a worktree
# beside build/, then the frame's stages (BM_FrameStages/512) and each method's kernel
# (BM_Method) run alternately, parent and change, twice each; every stage or benchmark whose
# best time got slower by more than 10 % is printed. Printed, never failing: machines are
# noisy. Needs build/ (the change) built; skips what the parent does not have.
set -uo pipefail
cd "$(dirname "$0")/.."
parent=${1:-HEAD^}
filter=${BENCH_FILTER:-'BM_FrameStages/512|BM_Method/'}
work=$(mktemp -d /tmp/pgt-bench-parent.XXXXXX)
cleanup() { git worktree remove --force "$work/src" >/dev/null 2>&1; rm -rf "$work"; }
trap cleanup EXIT
if ! git rev-parse --verify -q "$parent^{commit}" >/dev/null; then
  echo "bench_compare: no parent commit $parent in this clone: skipped"; exit 0
fi
echo "== benchmarks: $(git rev-parse --short HEAD) against its parent $(git rev-parse --short "$parent")"
git worktree add --detach "$work/src" "$parent" >/dev/null 2>&1 || { echo "bench_compare: no worktree: skipped"; exit 0; }
if ! { cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release >"$work/cmake.log" 2>&1 &&
       cmake --build "$work/build" -j2 --target pgt_bench >>"$work/cmake.log" 2>&1; }; then
  echo "bench_compare: the parent's pgt_bench does not build: skipped"; tail -5 "$work/cmake.log"; exit 0
fi
for round in 1 2; do
  for side in parent change; do
    bin=./build/tests/bench/pgt_bench
    [ "$side" = parent ] && bin="$work/build/tests/bench/pgt_bench"
    "$bin" --benchmark_filter="$filter" --benchmark_format=json --benchmark_min_time=0.2 \
      >"$work/$side.$round.json" 2>/dev/null || true
  done
done
/usr/bin/python3 - "$work" <<'PY'
import json, sys, glob
work = sys.argv[1]
def best(side):
    out = {}
    for path in glob.glob(f"{work}/{side}.*.json"):
        try:
            runs = json.load(open(path)).get("benchmarks", [])
        except ValueError:
            continue
        for b in runs:
            name = b["name"]
            values = {"time": b.get("real_time")}
            values.update({k: v for k, v in b.items() if k.endswith("_ms")})
            for k, v in values.items():
                if isinstance(v, (int, float)) and v > 0:
                    key = (name, k)
                    out[key] = min(out.get(key, v), v)
    return out
old, new = best("parent"), best("change")
common = sorted(set(old) & set(new))
slower = [(n, k, old[(n, k)], new[(n, k)]) for n, k in common if new[(n, k)] > 1.10 * old[(n, k)]
          and new[(n, k)] - old[(n, k)] > 2.0]
print(f"bench_compare: {len(common)} figures in both; {len(slower)} slower by more than 10 %:")
for n, k, a, b in slower:
    print(f"  {n} {k}: {a:.2f} -> {b:.2f} ({100 * (b / a - 1):+.0f} %)")
only = sorted({n for n, _ in set(new) - set(old)})
if only:
    print("  new in the change (no parent figure): " + ", ".join(only))
PY
exit 0
