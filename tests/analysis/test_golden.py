#!/usr/bin/python3
"""ctest: golden files. `pgt sweep tests/golden/study.json --images` must reproduce
tests/golden/results.csv and tests/golden/case_00000_summary.json: every number within
REL * |expected| + ABS, every string equal; measured times (ns_per_px, timings_ms, build
and tessellate ms) and paths are left out. Regenerate after an intended change with
  /usr/bin/python3 tests/analysis/test_golden.py build/src/pgt . --regenerate
and say in the commit why the numbers moved. Arguments: PGT_BINARY SOURCE_DIR [--regenerate]."""
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
# Embree's float hits may differ in the last bits between CPUs and builds (its kernels for
# SSE, AVX2, AVX-512); errors in texels move by far less than 1e-4 of themselves.
REL, ABS = 1e-4, 1e-6
sys.path.insert(0, os.path.join(SRC, "analysis"))
from columns import MEASURED_COLUMNS  # noqa: E402
SKIP_KEYS = set(MEASURED_COLUMNS) | {"timings_ms", "tessellate_ms", "build_ms", "scene_file", "glsl"}


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


def same(a, b, where, problems):
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            problems.append(f"{where}: keys {sorted(set(a) ^ set(b))} differ")
        for k in set(a) & set(b):
            same(a[k], b[k], f"{where}.{k}", problems)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            problems.append(f"{where}: {len(a)} vs {len(b)} items")
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{where}[{i}]", problems)
    elif isinstance(a, bool) or isinstance(b, bool) or number(a) is None or number(b) is None:
        if a != b:
            problems.append(f"{where}: {a!r} vs {b!r}")
    else:
        x, y = number(a), number(b)
        if math.isnan(x) and math.isnan(y):
            return
        if not abs(x - y) <= REL * abs(y) + ABS:
            problems.append(f"{where}: {x!r} vs expected {y!r}")


def csv_rows(path):
    with open(path, newline="") as f:
        return [{k: v for k, v in r.items() if k not in SKIP_KEYS} for r in csv.DictReader(f)]


with tempfile.TemporaryDirectory() as d:
    out = os.path.join(d, "study")
    r = subprocess.run([PGT, "sweep", os.path.join(GOLDEN, "study.json"), "--out", out,
                        "--images", "--no-report"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"sweep failed: {r.stderr}")
    summary = clean(json.load(open(os.path.join(out, "images", "case_00000", "summary.json"))))
    if "--regenerate" in sys.argv:
        shutil.copy(os.path.join(out, "results.csv"), os.path.join(GOLDEN, "results.csv"))
        with open(os.path.join(GOLDEN, "case_00000_summary.json"), "w") as f:
            json.dump(summary, f, indent=2, sort_keys=True)
            f.write("\n")
        print("regenerated tests/golden/results.csv and case_00000_summary.json")
        sys.exit(0)
    problems = []
    same(csv_rows(os.path.join(out, "results.csv")),
         csv_rows(os.path.join(GOLDEN, "results.csv")), "results.csv", problems)
    same(summary, json.load(open(os.path.join(GOLDEN, "case_00000_summary.json"))),
         "summary.json", problems)
    if problems:
        print("\n".join(problems[:40]))
        print(f"0 passed, 1 failed ({len(problems)} differences)")
        sys.exit(1)
    print("1 passed, 0 failed")
