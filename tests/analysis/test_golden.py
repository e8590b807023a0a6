#!/usr/bin/python3
"""ctest: golden files. `pgt sweep tests/golden/study.json --images` must reproduce
tests/golden/results.csv and tests/golden/case_00000_summary.json on every CPU: strings
equal, every number within its field's tolerance of tests/golden/tolerance.json; measured
times (ns_per_px, timings_ms, build and tessellate ms), paths and the provenance are left out.

What varies between machines is Embree's kernel: it picks SSE2, SSE4.2, AVX, AVX2 or AVX-512
code by the CPU, and their float hits differ in the last bits (a truth UV a float ulp or two
apart: a few 1e-6 texels on this 32-texel map). So the study runs here under every kernel
this CPU can run (PGT_EMBREE_ISA, docs/testing.md) and on one core (taskset -c 0), and
every run must match the golden files: a machine covers the CPUs it is not.

tolerance.json holds, per field, FACTOR x the largest difference measured between those runs
(a field that never moved must be equal). Measure it again after an intended change with
  /usr/bin/python3 tests/analysis/test_golden.py build/src/pgt . --regenerate
(the golden files from the default kernel, then the spread over every kernel), and say in the
commit why the numbers moved. Arguments: PGT_BINARY SOURCE_DIR [--regenerate]."""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

PGT, SRC = sys.argv[1], sys.argv[2]
GOLDEN = os.path.join(SRC, "tests", "golden")
TOLERANCE = os.path.join(GOLDEN, "tolerance.json")
# The tolerance is this many times the spread measured over Embree's five kernels and 1 vs 2
# cores: room for a CPU whose approximate reciprocals round differently from this one's.
FACTOR = 4
# Numbers are written with 9 significant digits: a field that never moved must agree to that.
PRINTED = 1e-8
sys.path.insert(0, os.path.join(SRC, "analysis"))
from columns import MEASURED_COLUMNS  # noqa: E402
SKIP_KEYS = set(MEASURED_COLUMNS) | {"timings_ms", "tessellate_ms", "build_ms", "scene_file", "glsl",
                                     "provenance"}  # what made it: the machine, the date


def cpu_flags():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("flags"):
                return set(line.split(":", 1)[1].split())
    return set()


def runs():
    """(name, command prefix, extra environment) of every way to run the study here."""
    flags = cpu_flags()
    needs = {"sse2": {"sse2"}, "sse4.2": {"sse4_2"}, "avx": {"avx"}, "avx2": {"avx2", "fma"},
             "avx512": {"avx512f", "avx512dq", "avx512cd", "avx512bw", "avx512vl"}}
    out = [("default", [], {})]
    out += [(f"isa={isa}", [], {"PGT_EMBREE_ISA": isa}) for isa, need in needs.items()
            if need <= flags]
    if shutil.which("taskset"):
        out.append(("one core", ["taskset", "-c", "0"], {}))
    return out


def clean(value):
    """The summary without measured times and machine-specific paths."""
    if isinstance(value, dict):
        return {k: clean(v) for k, v in value.items() if k not in SKIP_KEYS}
    if isinstance(value, list):
        return [clean(v) for v in value]
    return value


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def field_name(where):
    """A field's name without its row or list index: results.csv[3].p50 -> results.csv.p50."""
    out, skip = [], False
    for ch in where:
        if ch == "[":
            skip = True
        elif ch == "]":
            skip = False
        elif not skip:
            out.append(ch)
    return "".join(out)


def walk(a, b, where, visit):
    """Calls visit(field, a_value, b_value) for every leaf; returns structural differences."""
    problems = []
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            problems.append(f"{where}: keys {sorted(set(a) ^ set(b))} differ")
        for k in sorted(set(a) & set(b)):
            problems += walk(a[k], b[k], f"{where}.{k}", visit)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            problems.append(f"{where}: {len(a)} vs {len(b)} items")
        for i, (x, y) in enumerate(zip(a, b)):
            problems += walk(x, y, f"{where}[{i}]", visit)
    else:
        problems += visit(where, a, b)
    return problems


def difference(a, b):
    """|a - b| for two numbers (0 for two NaNs), None when either is not a number."""
    if isinstance(a, bool) or isinstance(b, bool) or number(a) is None or number(b) is None:
        return None
    x, y = number(a), number(b)
    if math.isnan(x) and math.isnan(y):
        return 0.0
    return abs(x - y) if not (math.isnan(x) or math.isnan(y)) else math.inf


def csv_rows(path):
    with open(path, newline="") as f:
        return [{k: v for k, v in r.items() if k not in SKIP_KEYS} for r in csv.DictReader(f)]


def run_study(name, prefix, env, d):
    out = os.path.join(d, name.replace(" ", "_").replace("=", "_"))
    r = subprocess.run(prefix + [PGT, "sweep", os.path.join(GOLDEN, "study.json"), "--out", out,
                                 "--images", "--no-report"],
                       capture_output=True, text=True, env={**os.environ, **env})
    if r.returncode != 0:
        sys.exit(f"sweep ({name}) failed: {r.stderr}")
    summary = clean(json.load(open(os.path.join(out, "images", "case_00000", "summary.json"))))
    return {"results.csv": csv_rows(os.path.join(out, "results.csv")), "summary.json": summary}, out


def compare(run, golden, tolerance):
    def visit(where, a, b):
        d = difference(a, b)
        if d is None:
            return [] if a == b else [f"{where}: {a!r} vs {b!r}"]
        y = abs(number(b)) if not math.isnan(number(b)) else 0.0
        allowed = tolerance.get(field_name(where), 0.0) + PRINTED * y
        return [] if d <= allowed else [f"{where}: {a!r} vs expected {b!r} (allowed {allowed:.3g})"]
    return walk(run, golden, "", visit)


def spread(all_runs):
    """Per field, the largest difference between any run and the first."""
    out = {}

    def visit(where, a, b):
        d = difference(a, b)
        if d is not None:
            key = field_name(where)
            out[key] = max(out.get(key, 0.0), d)
        return []
    for other in all_runs[1:]:
        walk(other, all_runs[0], "", visit)
    return out


def main():
    with tempfile.TemporaryDirectory() as d:
        results = []
        for name, prefix, env in runs():
            data, out = run_study(name, prefix, env, d)
            results.append((name, data, out))
        measured = spread([data for _, data, _ in results])
        if "--regenerate" in sys.argv:
            out = results[0][2]
            shutil.copy(os.path.join(out, "results.csv"), os.path.join(GOLDEN, "results.csv"))
            with open(os.path.join(GOLDEN, "case_00000_summary.json"), "w") as f:
                json.dump(results[0][1]["summary.json"], f, indent=2, sort_keys=True)
                f.write("\n")
            tol = {k: float(f"{FACTOR * v:.2g}") for k, v in sorted(measured.items()) if v > 0}
            with open(TOLERANCE, "w") as f:
                json.dump({"how": f"{FACTOR} x the largest difference between runs under "
                                  f"{', '.join(n for n, _, _ in results)} on one CPU "
                                  "(tests/analysis/test_golden.py --regenerate)",
                           "cpu": next((line.split(":", 1)[1].strip()
                                        for line in open("/proc/cpuinfo")
                                        if line.startswith("model name")), "?"),
                           "absolute": tol}, f, indent=2)
                f.write("\n")
            print("regenerated tests/golden/results.csv, case_00000_summary.json, tolerance.json")
            return 0
        tolerance = json.load(open(TOLERANCE))["absolute"]
        golden = {"results.csv": csv_rows(os.path.join(GOLDEN, "results.csv")),
                  "summary.json": json.load(open(os.path.join(GOLDEN, "case_00000_summary.json")))}
        failed = 0
        for name, data, _ in results:
            problems = compare(data, golden, tolerance)
            print(f"{name}: {len(problems)} differences beyond tolerance")
            if problems:
                failed += 1
                print("\n".join("  " + p for p in problems[:40]))
        moved = sorted(((v, k) for k, v in measured.items() if v > 0), reverse=True)
        print("spread between the runs here (largest first): " +
              ", ".join(f"{k} {v:.3g}" for v, k in moved[:8]))
        print(f"{len(results) - failed} passed, {failed} failed")
        return 1 if failed else 0


sys.exit(main())
