#!/usr/bin/python3
"""ctest: `pgt compare` on real seeded studies (docs/studies.md "Gating a shader change").

scenes/gate.json's study of 50 cases (10 view angles x 5 scales) with 30 replicate seeds is run once and cut
into 10 studies of 3 seeds each; then:
- 20 pairs of those (another jitter seed, nothing else changed) flag nothing (exit 0);
- a real change, POM's layers 8-32 -> 2-8 under the same label, is a regression that names it;
- relief made 1.3x worse at theta 40 only is flagged in that band and no other; one case out
  of 50 made 2x worse is flagged; everything 2x better is an improvement, exit 0;
- a renamed configuration is refused without --pair (exit 2) and judged with it; one seed is
  refused with the way out; another surface is refused, naming what differs;
- three studies give a history (history.csv, and its figure where matplotlib is).
Arguments: PGT_BINARY SOURCE_DIR."""
import copy
import csv
import json
import os
import subprocess
import sys
import tempfile

PGT, SRC = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SRC, "analysis"))
from study_split import read_rows, scaled, write_study  # noqa: E402
failures = []

# scenes/gate.json, the bundled gating study, with 30 seeds.
SCENE = json.load(open(os.path.join(SRC, "scenes", "gate.json")))
SCENE["sweep"]["replicates"] = 30


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + detail))
    if not ok:
        failures.append(name)


def run(*args):
    return subprocess.run([PGT, *args], capture_output=True, text=True, timeout=600)


def verdict(directory):
    return json.load(open(os.path.join(directory, "compare.json")))


with tempfile.TemporaryDirectory() as d:
    scene = os.path.join(d, "scene.json")
    json.dump(SCENE, open(scene, "w"))
    whole = os.path.join(d, "whole")
    r = run("sweep", scene, "--out", whole, "--no-report")
    check("the 30-seed study runs", r.returncode == 0, r.stderr[-2000:])
    identity = json.load(open(os.path.join(whole, "study.json")))
    rows = read_rows(whole)
    seeds = sorted({float(x["seed"]) for x in rows})
    check("30 seeds, 50 cases, 3 configurations", len(seeds) == 30 and len(rows) == 4500,
          f"{len(seeds)} seeds, {len(rows)} rows")
    groups = [seeds[3 * g:3 * g + 3] for g in range(10)]
    for g, group in enumerate(groups):
        write_study(os.path.join(d, f"g{g}"), identity, rows, group)

    # 20 pairs of seed groups: nothing changed but the seeds.
    flagged = []
    pairs = [(a, b) for a in range(10) for b in range(a + 1, 10)][:20]
    for a, b in pairs:
        out = os.path.join(d, f"cmp_{a}_{b}")
        r = run("compare", os.path.join(d, f"g{a}"), os.path.join(d, f"g{b}"), "--out", out,
                "--no-figures")
        if r.returncode != 0:
            flagged.append(f"g{a} vs g{b}: exit {r.returncode}: {r.stdout[-400:]}{r.stderr[-400:]}")
            continue
        cells = list(csv.DictReader(open(os.path.join(out, "compare.csv"))))
        changed = [c for c in cells if c["change"] != "unchanged"]
        if changed:
            flagged.append(f"g{a} vs g{b}: {len(changed)} bands changed")
    check("20 seed pairs flag nothing", not flagged, "; ".join(flagged))

    # A real change under the same label: POM with 2-8 layers instead of 8-32.
    worse = copy.deepcopy(SCENE)
    worse["methods"] = [{"name": "pom", "label": "pom", "min_layers": 2, "max_layers": 8}]
    worse["sweep"]["replicates"] = 3
    worse_scene = os.path.join(d, "worse.json")
    json.dump(worse, open(worse_scene, "w"))
    r = run("sweep", worse_scene, "--out", os.path.join(d, "pom2"), "--no-report")
    check("the 2-8 layers study runs", r.returncode == 0, r.stderr[-2000:])
    out = os.path.join(d, "cmp_pom2")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "pom2"), "--out", out)
    v = verdict(out) if os.path.exists(os.path.join(out, "compare.json")) else {}
    pom = [c for c in v.get("configurations", []) if c["label_old"] == "pom"]
    check("layers 8-32 -> 2-8 is a regression (exit 1)", r.returncode == 1 and pom and
          pom[0]["verdict"] == "regression", r.stdout + r.stderr)
    check("the verdict names the change", pom and pom[0]["changed"] == [
        "params.max_layers 32 → 8", "params.min_layers 8 → 2"], str(pom[0]["changed"] if pom else v))
    check("only in OLD noted", "only in" in r.stderr and "parallax" in r.stderr, r.stderr)

    # Relief 1.3x worse at theta 40 only (the same seeds: paired).
    g0 = [x for x in rows if float(x["seed"]) in groups[0]]
    band = scaled(g0, lambda x: 1.3 if x["label"] == "relief" and x["theta"] == "40" else 1)
    write_study(os.path.join(d, "band"), identity, band, groups[0])
    out = os.path.join(d, "cmp_band")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "band"), "--out", out)
    cells = list(csv.DictReader(open(os.path.join(out, "compare.csv")))) if r.returncode != 2 else []
    bad = [(c["label_old"], c["theta_lo"]) for c in cells if c["change"] == "regression"]
    check("1.3x at theta 40: exit 1, flagged there only", r.returncode == 1 and bad and
          all(b == ("relief", "40") for b in bad), f"exit {r.returncode}: {bad}")

    # The same with 3 other seeds (unpaired): reported, never flagged elsewhere.
    band_other = scaled([x for x in rows if float(x["seed"]) in groups[1]],
                        lambda x: 1.3 if x["label"] == "relief" and x["theta"] == "40" else 1)
    write_study(os.path.join(d, "band_other"), identity, band_other, groups[1])
    out = os.path.join(d, "cmp_band_other")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "band_other"), "--out", out)
    cells = list(csv.DictReader(open(os.path.join(out, "compare.csv")))) if r.returncode != 2 else []
    elsewhere = [(c["label_old"], c["theta_lo"]) for c in cells
                 if c["change"] != "unchanged" and (c["label_old"], c["theta_lo"]) != ("relief", "40")]
    check("1.3x at theta 40, other seeds: nothing flagged elsewhere", r.returncode in (0, 1)
          and not elsewhere, f"exit {r.returncode}: {elsewhere}")

    # One case of 50 twice as bad (relief, theta 70, s 0.06).
    one = scaled(g0, lambda x: 2 if x["label"] == "relief" and x["theta"] == "70"
                 and x["scale"] == "0.06" else 1)
    write_study(os.path.join(d, "one"), identity, one, groups[0])
    out = os.path.join(d, "cmp_one")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "one"), "--out", out)
    cells = list(csv.DictReader(open(os.path.join(out, "compare.csv")))) if r.returncode != 2 else []
    bad = [(c["label_old"], c["theta_lo"], c["scale"]) for c in cells if c["change"] != "unchanged"]
    check("one case of 50 at 2x is flagged", r.returncode == 1 and
          bad == [("relief", "70", "0.06")], f"exit {r.returncode}: {bad}")

    # Everything twice as good, other seeds: an improvement, never a regression.
    better = scaled([x for x in rows if float(x["seed"]) in groups[2]], lambda x: 0.5)
    write_study(os.path.join(d, "better"), identity, better, groups[2])
    out = os.path.join(d, "cmp_better")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "better"), "--out", out)
    v = verdict(out) if r.returncode != 2 else {}
    check("2x better: exit 0, improvements only", r.returncode == 0 and all(
        c["verdict"] == "improvement" for c in v.get("configurations", [])), r.stdout + r.stderr)

    # A renamed configuration: refused without --pair, judged with it.
    renamed = [dict(x, label="relief_v2") if x["label"] == "relief" else x for x in g0]
    write_study(os.path.join(d, "renamed"), identity, renamed, groups[0])
    out = os.path.join(d, "cmp_renamed")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "renamed"), "--out", out)
    check("a rename without --pair: exit 2 naming --pair", r.returncode == 2 and "--pair" in r.stderr
          and "relief_v2" in r.stderr and not os.path.exists(out), r.stderr)
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "renamed"), "--out", out,
            "--pair", "relief=relief_v2")
    v = verdict(out) if r.returncode == 0 else {}
    check("with --pair: judged, unchanged", r.returncode == 0 and any(
        c["label_new"] == "relief_v2" and c["verdict"] == "unchanged"
        for c in v.get("configurations", [])), r.stdout + r.stderr)

    # One seed: refused, with the way out.
    write_study(os.path.join(d, "single"), identity, g0, [groups[0][0]])
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "single"), "--out",
            os.path.join(d, "cmp_single"))
    check("one seed: exit 2 naming replicates", r.returncode == 2 and "replicates" in r.stderr,
          r.stderr)

    # Another surface: refused naming it; --any-scene compares anyway.
    other = copy.deepcopy(identity)
    other["scene"]["heightmap"]["seed"] = 4
    write_study(os.path.join(d, "other"), other, g0, groups[0])
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "other"), "--out",
            os.path.join(d, "cmp_other"))
    check("another surface: exit 2 naming heightmap", r.returncode == 2 and
          "heightmap" in r.stderr and "--any-scene" in r.stderr, r.stderr)
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "other"), "--out",
            os.path.join(d, "cmp_other"), "--any-scene")
    check("--any-scene compares", r.returncode == 0, r.stderr)

    # A history of three studies.
    out = os.path.join(d, "cmp_history")
    r = run("compare", os.path.join(d, "g0"), os.path.join(d, "g1"), os.path.join(d, "band"),
            "--out", out)
    hist = list(csv.DictReader(open(os.path.join(out, "history.csv")))) if r.returncode != 2 else []
    check("history: 3 studies x 3 configurations", len(hist) == 9 and r.returncode == 1,
          f"exit {r.returncode}, {len(hist)} rows: {r.stderr}")
    md = open(os.path.join(out, "compare.md")).read() if os.path.exists(out) else ""
    check("compare.md states the verdict and the test", "REGRESSION" in md and "Benjamini-Hochberg" in md, md)
    try:
        import matplotlib  # noqa: F401
        have_plots = True
    except ImportError:
        have_plots = False
    if have_plots:
        figs = os.listdir(os.path.join(out, "figures")) if os.path.isdir(
            os.path.join(out, "figures")) else []
        check("figures: history and one ratio per configuration, PNG and SVG",
              {"history.png", "history.svg", "ratio_relief.png", "ratio_pom.svg"} <= set(figs),
              str(figs))
        check("compare.md links the figures", "figures/history.png" in md, md)

    # Bad options.
    for args, word in [(["--bands", "30,10"], "--bands"), (["--metric", "median"], "--metric"),
                       (["--alpha", "0"], "--alpha")]:
        r = run("compare", os.path.join(d, "g0"), os.path.join(d, "g1"), "--out",
                os.path.join(d, "cmp_bad"), *args)
        check(f"bad {word}: exit 2", r.returncode == 2 and word in r.stderr, r.stderr)
    r = run("compare", os.path.join(d, "g0"), d, "--out", os.path.join(d, "cmp_bad"))
    check("not a study: exit 2", r.returncode == 2 and "study" in r.stderr, r.stderr)

if failures:
    print(f"{len(failures)} failed: {', '.join(failures)}")
    sys.exit(1)
print("all passed")
