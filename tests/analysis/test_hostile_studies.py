#!/usr/bin/python3
"""ctest: studies under kills, edits and hostile directories, one class per ctest
(docs/testing.md "What pgt promises"): rows land per case, merge never loses a finished
study, shards are checked against their plan, clusters' task ids map to shards. Arguments:
PGT_BINARY SOURCE_DIR CLASS."""
import fcntl
import json
import os
import shutil
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


def shards_of(d, scene, n, name="s"):
    """Runs every shard of a study (--shard I/n); returns their directories."""
    path = write(d, f"{name}.json", json.dumps(scene))
    dirs = []
    for i in range(n):
        out = os.path.join(d, f"{name}_{i}")
        r = sweep(path, out, "--shard", f"{i}/{n}")
        check(f"shard {i}/{n}", r.returncode == 0, r.stderr)
        dirs.append(out)
    return path, dirs


def merge(dirs, out, *extra):
    return run(["merge", *dirs, "--out", out, "--no-report", *extra])


def merge_data_loss(d):
    """pgt merge never replaces a finished study: an input shard as --out (directly or through
    a symlink), a directory holding another study, and a directory a sweep holds are refused,
    and nothing in them changes; merging again into the same study's directory works."""
    _, dirs = shards_of(d, SWEEP, 2)
    before = [open(os.path.join(x, "results.csv")).read() for x in dirs]
    expect_error("--out is a shard", merge(dirs, dirs[0]), 2, ["--out", "is the shard"])
    os.symlink(dirs[1], os.path.join(d, "link"))
    expect_error("--out links to a shard", merge(dirs, os.path.join(d, "link")), 2,
                 ["--out", "is the shard"])
    check("shards unchanged", before == [open(os.path.join(x, "results.csv")).read()
                                         for x in dirs])
    other = copy(SWEEP)
    other["sweep"]["theta"] = [10, 30]
    path = write(d, "other.json", json.dumps(other))
    finished = os.path.join(d, "finished")
    check("another study", sweep(path, finished).returncode == 0)
    kept = open(os.path.join(finished, "results.csv")).read()
    expect_error("--out holds another study", merge(dirs, finished), 2,
                 ["study.json", "different study"])
    check("the other study unchanged", kept == open(os.path.join(finished, "results.csv")).read())
    held = os.path.join(d, "held")
    os.makedirs(held)
    with open(os.path.join(held, ".pgt-lock"), "w") as lock:  # as a running sweep holds it
        fcntl.flock(lock, fcntl.LOCK_EX)
        expect_error("--out locked by a sweep", merge(dirs, held), 3, ["in use"])
    check("nothing written while locked", sorted(os.listdir(held)) == [".pgt-lock"],
          f"{os.listdir(held)}")
    out = os.path.join(d, "merged")
    r1, r2 = merge(dirs, out), merge(dirs, out)
    check("merge, then merge again", r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr)


def edited(d, dirs, name, edit_csv=None, edit_study=None):
    """A copy of the shards with shard 0's results.csv or study.json edited."""
    copies = []
    for i, src in enumerate(dirs):
        dst = os.path.join(d, f"{name}_{i}")
        shutil.copytree(src, dst)
        copies.append(dst)
    if edit_csv:
        path = os.path.join(copies[0], "results.csv")
        rows = open(path).read().split("\n")
        open(path, "w").write("\n".join(edit_csv(rows)))
    if edit_study:
        path = os.path.join(copies[0], "study.json")
        j = json.load(open(path))
        edit_study(j["shard"])
        json.dump(j, open(path, "w"))
    return copies


def merge_edited_shards(d):
    """Every row is checked against the study's plan: hand-edited case indices, angles, scales,
    methods, parameters and labels (unknown or twice) are exit 2 naming the shard's
    results.csv, the line and the field; a malformed shard block is exit 2, never 1."""
    scene = copy(SWEEP)
    scene["sweep"]["pom.max_layers"] = [8, 16]
    _, dirs = shards_of(d, scene, 2)
    field = lambda row, k, v: ",".join(row.split(",")[:k] + [v] + row.split(",")[k + 1:])  # noqa: E731
    cases = [
        ("case 7x", lambda rows: [rows[0], field(rows[1], 0, "2x")] + rows[2:], ["line 2: case"]),
        ("case 2.0", lambda rows: [rows[0], field(rows[1], 0, "2.0")] + rows[2:], ["case"]),
        ("case ' 2'", lambda rows: [rows[0], field(rows[1], 0, " 2")] + rows[2:], ["case"]),
        ("another shard's case", lambda rows: [rows[0], field(rows[1], 0, "1")] + rows[2:],
         ["case", "not a case of shard 0"]),
        ("theta", lambda rows: [rows[0], field(rows[1], 1, "21")] + rows[2:], ["theta"]),
        ("scale", lambda rows: [rows[0], field(rows[1], 3, "0.03")] + rows[2:], ["scale"]),
        ("unknown label", lambda rows: [rows[0], rows[1].replace(",parallax,parallax,",
                                                                 ",parallax,parallaxX,")] + rows[2:],
         ["label", "not a configuration"]),
        ("method", lambda rows: [rows[0], rows[1].replace(",parallax,parallax,", ",pom,parallax,")]
         + rows[2:], ["method"]),
        ("label twice", lambda rows: [rows[0], rows[1], rows[1]] + rows[3:], ["label", "twice"]),
    ]
    for name, edit, words in cases:
        copies = edited(d, dirs, name.replace(" ", "_").replace("'", ""), edit_csv=edit)
        expect_error(f"edited {name}", merge(copies, os.path.join(d, "out")), 2,
                     ["results.csv"] + words, os.path.join(d, "out"))
    blocks = [("labels missing", lambda s: s.pop("labels"), "labels"),
              ("labels a number", lambda s: s.update(labels=3), "labels"),
              ("labels an object", lambda s: s.update(labels={"a": 1}), "labels"),
              ("an unknown key", lambda s: s.update(extra=1), "extra")]
    for name, edit, word in blocks:
        copies = edited(d, dirs, "block_" + name.replace(" ", "_"), edit_study=edit)
        expect_error(f"shard block: {name}", merge(copies, os.path.join(d, "out")), 2,
                     ["study.json", word], os.path.join(d, "out"))


def merge_memory(d):
    """A shard's `cases` is bounded by a study's 10^6 (2^30 was accepted and allocated 4.2 GB);
    merge takes --memory-limit like every other command."""
    _, dirs = shards_of(d, SWEEP, 2)
    copies = edited(d, dirs, "huge", edit_study=lambda s: s.update(cases=1 << 30))
    r = merge(copies, os.path.join(d, "out"))
    expect_error("cases 2^30", r, 2, ["study.json", "cases"], os.path.join(d, "out"))
    r = merge(dirs, os.path.join(d, "ok"), "--memory-limit", "64")
    check("merge --memory-limit 64", r.returncode == 0, r.stderr)


def slurm_semantics(d):
    """--shard slurm: the shard is the array index and N is given (slurm:N), the resumed shard
    directory's, or a plain 0..N-1 array's; a resubmitted single task (--array=1) runs shard 1,
    never the whole study, and a stepped array (0-4:2) maps 0, 2, 4 to shards 0, 2, 4."""
    path = write(d, "study.json", json.dumps(SWEEP))
    base = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}

    def array(task, lo, hi, count, value, out):
        env = dict(base, SLURM_ARRAY_TASK_ID=str(task), SLURM_ARRAY_TASK_MIN=str(lo),
                   SLURM_ARRAY_TASK_MAX=str(hi), SLURM_ARRAY_TASK_COUNT=str(count))
        return run(["sweep", path, "--out", out, "--no-report", "--shard", value], env=env)

    def shard_of(out):
        s = json.load(open(os.path.join(out, "study.json")))["shard"]
        return s["index"], s["count"]

    out = os.path.join(d, "shard_1")
    r = array(1, 1, 1, 1, "slurm:3", out)  # sbatch --array=1 of a 3-shard study
    check("resubmitted task with slurm:3 runs shard 1/3", r.returncode == 0 and
          shard_of(out) == (1, 3), r.stderr)
    r = array(1, 1, 1, 1, "slurm", out)  # again, N from the shard's own directory
    check("resubmitted task resumes its shard", r.returncode == 0 and "resumed" in r.stdout and
          shard_of(out) == (1, 3), r.stderr)
    expect_error("resubmitted task without N or its directory",
                 array(1, 1, 1, 1, "slurm", os.path.join(d, "none")), 2, ["--shard", "slurm:N"])
    expect_error("stepped array without N", array(2, 0, 4, 3, "slurm", os.path.join(d, "st")), 2,
                 ["--shard", "slurm:N"])
    for task in (0, 2, 4):
        out = os.path.join(d, f"stepped_{task}")
        r = array(task, 0, 4, 3, "slurm:5", out)
        check(f"stepped array task {task} with slurm:5", r.returncode == 0 and
              shard_of(out) == (task, 5), r.stderr)
    out = os.path.join(d, "plain")
    r = array(2, 0, 2, 3, "slurm", out)
    check("plain 0..2 array: shard 2/3", r.returncode == 0 and shard_of(out) == (2, 3), r.stderr)


def small_options(d):
    """--shard '' and --max-cases -5 ran the whole study; they are refused."""
    path = write(d, "study.json", json.dumps(SWEEP))
    for args, word in [(["--shard", ""], "--shard"), (["--max-cases", "-5"], "--max-cases")]:
        out = os.path.join(d, "out")
        expect_error(" ".join(args), sweep(path, out, *args), 2, [word], out)


if __name__ == "__main__":
    main([rows_per_case, merge_data_loss, merge_edited_shards, merge_memory, slurm_semantics,
          small_options])
