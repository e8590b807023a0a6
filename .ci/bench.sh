#!/usr/bin/env bash
# docs/performance.md measurements in one command: the Google Benchmark targets (build, refit vs rebuild,
# truth frame vs the bare Embree loop, coherent vs single rays, each method's ns/px), then the
# end-to-end figures that Google Benchmark cannot hold: the default study's wall time, peak
# memory of the 1024^2 and 4096^2 map renders, and the scaling with pixels and with cases.
# Timings are not assertions; this machine is noisy (ratios within one run are what count).
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/deps.sh
bash .ci/build.sh
PGT=./build/src/pgt
OUT=${BENCH_OUT:-out/bench}
mkdir -p "$OUT"
./build/tests/bench/pgt_bench --benchmark_min_time=0.5 "$@"

timed() {  # label, command...: prints wall seconds and peak RSS
    local label=$1; shift
    /usr/bin/time -f "$label: %e s wall, %M KB peak" "$@" >"$OUT/last.log" 2>"$OUT/time.log" || {
        cat "$OUT/last.log" "$OUT/time.log"; return 1; }
    grep -E "stage totals|done in|uncertainty|blocks" "$OUT/last.log" || true
    tail -1 "$OUT/time.log"
}

echo "== default study, end to end (sweep + report)"
timed "default study" $PGT sweep scenes/default.json --out "$OUT/study" --fresh

echo "== peak memory: 1024^2 and 4096^2 maps"
/usr/bin/python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
s = json.load(open("scenes/stress/large/map_4096.json"))
s["heightmap"]["size"] = [1024, 1024]
s["heightmap"]["frequency"] = 8
json.dump(s, open(f"{out}/map_1024.json", "w"))
d = json.load(open("scenes/default.json"))
for name, res in [("px1", 64), ("px4", 128)]:
    e = dict(d); e["sweep"] = dict(d["sweep"]); e["sweep"]["resolution"] = [res, res]
    json.dump(e, open(f"{out}/scaling_{name}.json", "w"))
PY
timed "map 1024^2 (rate 2 + uncertainty)" $PGT render "$OUT/map_1024.json" --out "$OUT/map_1024"
timed "map 4096^2 (rate 2 + uncertainty)" $PGT render scenes/stress/large/map_4096.json --out "$OUT/map_4096"

echo "== scaling with pixels (default study at 64^2 and 128^2, no report)"
timed "64^2 pixels" $PGT sweep "$OUT/scaling_px1.json" --out "$OUT/px1" --fresh --no-report
timed "128^2 pixels" $PGT sweep "$OUT/scaling_px4.json" --out "$OUT/px4" --fresh --no-report
echo "== scaling with cases (default study, 45 and 180 cases, no report)"
timed "45 cases" $PGT sweep scenes/default.json --out "$OUT/c1" --fresh --no-report --max-cases 45
timed "180 cases" $PGT sweep scenes/default.json --out "$OUT/c4" --fresh --no-report --max-cases 180

echo "== pgt render of the default scene with none, parallax, pom: 512^2 to 8192^2"
/usr/bin/python3 - "$OUT" <<'PY'
import json, sys
d = json.load(open("scenes/default.json"))
for r in [512, 1024, 2048, 4096, 8192]:
    e = dict(d); e["camera"] = dict(d["camera"]); e["camera"]["resolution"] = [r, r]
    e["methods"] = ["none", "parallax", {"name": "pom", "min_layers": 8, "max_layers": 32}]
    json.dump(e, open(f"{sys.argv[1]}/frame_{r}.json", "w"))
PY
for r in 512 1024 2048 4096 8192; do
  /usr/bin/time -f "frame $r^2: %e s wall, %M KB peak" $PGT render "$OUT/frame_$r.json" \
    --out "$OUT/frame_$r" 2>&1 | grep -E "stages|wall"
done

echo "== default study on 1 core and on all cores (no report)"
timed "1 core" taskset -c 0 $PGT sweep scenes/default.json --out "$OUT/cores1" --fresh --no-report
timed "all cores" $PGT sweep scenes/default.json --out "$OUT/coresN" --fresh --no-report
