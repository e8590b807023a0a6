#!/usr/bin/python3
"""ctest: studies under kills, edits and hostile directories, one class per ctest
(docs/testing.md "What pgt promises"): rows land per case, merge never loses a finished
study, shards are checked against their plan, clusters' task ids map to shards. Arguments:
PGT_BINARY SOURCE_DIR CLASS."""
import json
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_common import *  # noqa: E402,F401,F403  (the harness: run, check, scenes, ...)


def rows_per_case(d):
    """A finished case's rows are on disk before its surface (s, b) is done: a SIGKILL in the
    middle of one surface's 18 cases leaves whole cases, and the resumed study equals an
    uninterrupted one."""
    scene = copy(SWEEP)
    scene["heightmap"]["size"] = [64, 64]
    scene["camera"]["resolution"] = [128, 128]
    scene["methods"] = ["parallax", {"name": "pom", "min_layers": 32, "max_layers": 64},
                        {"name": "relief", "linear_steps": 40}]
    scene["truth"] = {"rate": 4}
    scene["sweep"] = {"theta": list(range(0, 90, 5)), "scale": [0.05],
                      "timing": {"repeats": 3, "fragments": 4096}}
    path = write(d, "scene.json", json.dumps(scene))
    whole = os.path.join(d, "whole")
    r = sweep(path, whole)
    check("uninterrupted", r.returncode == 0, r.stderr)
    killed = os.path.join(d, "killed")
    csv_path = os.path.join(killed, "results.csv")
    p = subprocess.Popen([PGT, "sweep", path, "--out", killed, "--no-report"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline, landed = time.time() + 120, 0
    while time.time() < deadline and p.poll() is None:
        if os.path.exists(csv_path):
            landed = sum(1 for _ in open(csv_path)) - 1
            if landed > 0:
                break
        time.sleep(0.005)
    running = p.poll() is None
    p.send_signal(signal.SIGKILL)
    p.wait()
    rows = rows_of(csv_path)
    cases = {}
    for row in rows:
        cases.setdefault(row["case"], []).append(row["label"])
    check("rows landed while the one surface was running", running and 0 < len(rows) < 18 * 3,
          f"running {running}, {len(rows)} rows")
    check("whole cases only", all(sorted(v) == ["parallax", "pom", "relief"]
                                  for v in cases.values()), f"{cases}")
    r = sweep(path, killed)
    check("resumes", r.returncode == 0 and "resumed" in r.stdout, r.stderr)
    check("resumed equals uninterrupted", key_rows(csv_path) == key_rows(
        os.path.join(whole, "results.csv")))
    order = [int(row["case"]) for row in rows_of(csv_path)]
    check("rows in case order", order == sorted(order), f"{order}")


if __name__ == "__main__":
    main([rows_per_case])
