#!/usr/bin/python3
"""How well `pgt compare` tells a change from seed noise on YOUR scene (docs/studies.md).

Runs the scene's study once with many replicate seeds (--seeds, default 60), cuts it into
studies of R seeds each (R = 2, 3, 5, 10) and runs `pgt compare` on them:
- false alarms: pairs of those studies (drawn with a fixed seed) differ in their seeds only;
  the share of pairs with any band flagged is the gate's false-alarm rate at that R;
- power: the first configuration made worse by a factor f in one band of view angles (every
  scale) in the NEW study of each pair (other seeds: the unpaired case); the share of those
  bands flagged, per f.
Writes OUT/calibration.md and OUT/calibration.csv and prints the table.
Usage: /usr/bin/python3 analysis/compare_calibration.py SCENE OUT [--pgt PGT] [--seeds 60]
       [--pairs 30] [--theta 40] [--label LABEL]"""
import argparse
import copy
import csv
import json
import os
import random
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_split import read_rows, scaled, write_study  # noqa: E402

FACTORS = [1.1, 1.2, 1.3, 1.5, 2.0, 3.0]


def compare(pgt, old, new, out):
    r = subprocess.run([pgt, "compare", old, new, "--out", out, "--no-figures"],
                       capture_output=True, text=True)
    if r.returncode == 2:
        sys.exit(f"compare_calibration.py: pgt compare failed: {r.stderr}")
    with open(os.path.join(out, "compare.csv"), newline="") as f:
        return list(csv.DictReader(f))


def calibrate(args, identity, rows, seeds, label, size):
    """False alarms and power with `size` seeds a side: a row of the table, or None."""
    groups = [seeds[size * g:size * g + size] for g in range(len(seeds) // size)]
    every = [(a, b) for a in range(len(groups)) for b in range(a + 1, len(groups))]
    pairs = random.Random(size).sample(every, min(args.pairs, len(every)))
    if not pairs:
        return None
    alarms, cells, flagged = 0, 0, {f: 0 for f in FACTORS}
    for a, b in pairs:
        old = os.path.join(args.out, f"r{size}_g{a}")
        new = os.path.join(args.out, f"r{size}_g{b}")
        for g, path in ((a, old), (b, new)):
            if not os.path.exists(path):
                write_study(path, identity, rows, groups[g])
        got = compare(args.pgt, old, new, os.path.join(args.out, "cmp"))
        alarms += any(c["change"] != "unchanged" for c in got)
        for f in FACTORS:
            worse = os.path.join(args.out, f"r{size}_g{b}_x{f}")
            if not os.path.exists(worse):
                write_study(worse, identity, scaled(rows, lambda x: f if (
                    x["label"] == label and x["theta"] == args.theta) else 1), groups[b])
            got = compare(args.pgt, old, worse, os.path.join(args.out, "cmp"))
            band = [c for c in got if c["label_old"] == label and c["theta_lo"] == args.theta]
            flagged[f] += sum(c["change"] == "regression" for c in band)
            cells = len(band)
    row = {"replicates": size, "pairs": len(pairs), "false_alarm_rate": alarms / len(pairs)}
    for f in FACTORS:
        row[f"detected_x{f:g}"] = flagged[f] / (cells * len(pairs))
    print(row, flush=True)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--pgt", default="pgt")
    ap.add_argument("--seeds", type=int, default=60)
    ap.add_argument("--pairs", type=int, default=30, help="pairs of studies per R (seeded draw)")
    ap.add_argument("--label", help="the configuration made worse (default: the first)")
    ap.add_argument("--theta", default="40", help="the band made worse (one of the study's)")
    args = ap.parse_args()
    scene = json.load(open(args.scene))
    scene = copy.deepcopy(scene)
    scene.setdefault("sweep", {}).pop("seed", None)
    scene["sweep"]["replicates"] = args.seeds
    scene["sweep"]["samples"] = "jittered"
    os.makedirs(args.out, exist_ok=True)
    scene_path = os.path.join(args.out, "scene.json")
    base = os.path.dirname(os.path.abspath(args.scene))
    json.dump(scene, open(scene_path, "w"))
    study = os.path.join(args.out, "study")
    r = subprocess.run([args.pgt, "sweep", scene_path, "--out", study, "--no-report"], cwd=base)
    if r.returncode != 0:
        return r.returncode
    identity = json.load(open(os.path.join(study, "study.json")))
    rows = read_rows(study)
    seeds = sorted({float(x["seed"]) for x in rows})
    label = args.label or rows[0]["label"]
    if label not in {x["label"] for x in rows}:
        sys.exit(f"compare_calibration.py: --label {label}: not a configuration of the study")
    table = [row for size in (2, 3, 5, 10)
             if (row := calibrate(args, identity, rows, seeds, label, size)) is not None]
    with open(os.path.join(args.out, "calibration.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        w.writeheader()
        w.writerows(table)
    lines = [f"# pgt compare calibration: {args.scene}", "",
             f"{args.seeds} seeds; pairs of studies of R seeds each (other seeds: unpaired); "
             f"`{label}` made worse by a factor in the theta {args.theta} band.", "",
             "| R | pairs | false alarms | " + " | ".join(f"x{f:g} found" for f in FACTORS) + " |",
             "|---" * (3 + len(FACTORS)) + "|"]
    for row in table:
        lines.append(f"| {row['replicates']} | {row['pairs']} | {row['false_alarm_rate']:.0%} | " +
                     " | ".join(f"{row[f'detected_x{f:g}']:.0%}" for f in FACTORS) + " |")
    open(os.path.join(args.out, "calibration.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
