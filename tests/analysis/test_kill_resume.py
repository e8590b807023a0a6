#!/usr/bin/python3
"""ctest: nothing lost. A real `pgt sweep` child process is killed with SIGKILL mid-run, the
same command is run again on the same directory, and the result must equal an uninterrupted
run's (all columns but the measured ns_per_px, order-independent). Arguments: PGT SOURCE."""
import csv
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(sys.argv[2], "analysis"))
from columns import without_measured  # noqa: E402

pgt = sys.argv[1]
scene = {
    "heightmap": {"procedural": "sine", "size": [64, 64]},
    "base": {"type": "plane", "infinite": True},
    "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [96, 96]},
    "methods": ["parallax", {"name": "pom", "min_layers": 8, "max_layers": 64}, "relief"],
    "truth": {"rate": 4},
    "sweep": {"theta": {"from": 0, "to": 80, "step": 5}, "scale": [0.03, 0.06],
              "timing": {"repeats": 1, "fragments": 256}},
}


def rows(path):
    with open(path, newline="") as f:
        return sorted(without_measured(r) for r in csv.DictReader(f))


def sweep(path, out, **kw):
    return subprocess.run([pgt, "sweep", path, "--out", out, "--no-report"], capture_output=True,
                          text=True, **kw)


with tempfile.TemporaryDirectory() as d:
    path = os.path.join(d, "scene.json")
    json.dump(scene, open(path, "w"))
    whole = os.path.join(d, "whole")
    r = sweep(path, whole)
    if r.returncode != 0:
        sys.exit(f"uninterrupted sweep failed: {r.stderr}")
    killed = os.path.join(d, "killed")
    csv_path = os.path.join(killed, "results.csv")
    p = subprocess.Popen([pgt, "sweep", path, "--out", killed, "--no-report"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    # Kill once some cases are on disk but not all (34 cases of 3 rows each).
    deadline = time.time() + 120
    while time.time() < deadline and p.poll() is None:
        if os.path.exists(csv_path) and sum(1 for _ in open(csv_path)) > 1 + 3 * 3:
            break
        time.sleep(0.01)
    if p.poll() is not None:
        sys.exit("the sweep finished before it could be killed; make the study slower")
    p.send_signal(signal.SIGKILL)
    p.wait()
    partial = sum(1 for _ in open(csv_path)) - 1
    r = sweep(path, killed)
    if r.returncode != 0:
        sys.exit(f"resumed sweep failed: {r.stderr}")
    if "resumed" not in r.stdout:
        sys.exit(f"no resume reported: {r.stdout}")
    if rows(os.path.join(whole, "results.csv")) != rows(csv_path):
        sys.exit("the resumed results differ from the uninterrupted run")
print(f"killed after {partial} rows; resumed run equals the uninterrupted one")
print("1 passed, 0 failed")
