#!/usr/bin/python3
"""ctest: a study split into shards (pgt sweep --shard I/N) and joined again (pgt merge) is
the study run on one machine; merge refuses a missing shard, a shard of another study and a
torn shard; bad --shard values are bad input; a shard killed and resumed still merges to the
same rows. Arguments: PGT_BINARY SOURCE_DIR."""
import json
import os
import subprocess
import sys
import tempfile

PGT, SRC = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from small_study import SCENE, rows  # noqa: E402

failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + detail))
    if not ok:
        failures.append(name)


def run(*args, env=None):
    return subprocess.run([PGT, *args], capture_output=True, text=True, timeout=300,
                          env=env or os.environ)


def one_error(r, status, words):
    lines = [l for l in r.stderr.splitlines() if l.strip()]
    return r.returncode == status and len(lines) == 1 and all(w in lines[0] for w in words)


with tempfile.TemporaryDirectory() as d:
    scene = os.path.join(d, "scene.json")
    json.dump(SCENE, open(scene, "w"))
    whole = os.path.join(d, "whole")
    r = run("sweep", scene, "--out", whole, "--no-report")
    check("unsharded run", r.returncode == 0, r.stderr)
    want = rows(whole)
    check("the study has rows", len(want) == 5 * 2 * 2 * 3, str(len(want)))

    shards = [os.path.join(d, f"s{i}") for i in range(3)]
    for i, out in enumerate(shards):
        r = run("sweep", scene, "--out", out, "--no-report", "--shard", f"{i}/3")
        check(f"shard {i}/3", r.returncode == 0, r.stderr)
    merged = os.path.join(d, "merged")
    r = run("merge", *shards, "--out", merged, "--no-report")
    check("merge of 3 shards", r.returncode == 0, r.stderr)
    check("merged rows = one run", rows(merged) == want)
    check("merged study.json = one run's",
          json.load(open(os.path.join(merged, "study.json"))) ==
          json.load(open(os.path.join(whole, "study.json"))))
    r = run("merge", *reversed(shards), "--out", os.path.join(d, "merged2"), "--no-report")
    check("merge in another order", r.returncode == 0 and rows(os.path.join(d, "merged2")) == want,
          r.stderr)
    # The merged directory is a normal study: resuming it runs nothing.
    r = run("sweep", scene, "--out", merged, "--no-report")
    check("a merged study resumes as complete", r.returncode == 0 and "0 cases run" in r.stdout,
          r.stdout + r.stderr)

    r = run("merge", shards[0], shards[2], "--out", os.path.join(d, "m1"), "--no-report")
    check("a missing shard: exit 2 naming the cases",
          one_error(r, 2, ["missing", "2 of 3", "1, 4, 7"]), r.stderr)

    other = dict(SCENE, sweep=dict(SCENE["sweep"], theta=[0, 20, 40, 60, 85]))
    other_scene = os.path.join(d, "other.json")
    json.dump(other, open(other_scene, "w"))
    o1 = os.path.join(d, "o1")
    run("sweep", other_scene, "--out", o1, "--no-report", "--shard", "1/3")
    r = run("merge", shards[0], o1, shards[2], "--out", os.path.join(d, "m2"), "--no-report")
    check("a shard of another study: exit 2", one_error(r, 2, ["another study", "o1"]), r.stderr)

    torn = os.path.join(d, "torn")
    run("sweep", scene, "--out", torn, "--no-report", "--shard", "1/3")
    path = os.path.join(torn, "results.csv")
    text = open(path).read()
    open(path, "w").write(text[: len(text) - 40])
    r = run("merge", shards[0], torn, shards[2], "--out", os.path.join(d, "m3"), "--no-report")
    check("a torn shard: exit 2", one_error(r, 2, ["torn", "results.csv"]), r.stderr)
    # The same shard resumed (the torn case is run again) merges to the same rows.
    r = run("sweep", scene, "--out", torn, "--no-report", "--shard", "1/3")
    r2 = run("merge", shards[0], torn, shards[2], "--out", os.path.join(d, "m4"), "--no-report")
    check("the torn shard resumed merges to one run",
          r.returncode == 0 and r2.returncode == 0 and rows(os.path.join(d, "m4")) == want,
          r.stderr + r2.stderr)

    # A shard stopped early and resumed (as a killed job re-queued would be).
    part = os.path.join(d, "part")
    r = run("sweep", scene, "--out", part, "--no-report", "--shard", "2/3", "--max-cases", "2")
    check("a shard stopped early", r.returncode == 0 and "stopped early" in r.stdout, r.stdout)
    r = run("sweep", scene, "--out", part, "--no-report", "--shard", "2/3")
    r2 = run("merge", shards[0], shards[1], part, "--out", os.path.join(d, "m5"), "--no-report")
    check("stopped, resumed, merged = one run",
          r.returncode == 0 and r2.returncode == 0 and rows(os.path.join(d, "m5")) == want,
          r.stderr + r2.stderr)

    # --shard slurm takes I from the job array's index and N from slurm:N (or a plain
    # 0..N-1 array; hostile.slurm_semantics has the other cases).
    env = dict(os.environ, SLURM_ARRAY_TASK_ID="1", SLURM_ARRAY_TASK_MIN="0",
               SLURM_ARRAY_TASK_MAX="2", SLURM_ARRAY_TASK_COUNT="3")
    sl = os.path.join(d, "slurm1")
    r = run("sweep", scene, "--out", sl, "--no-report", "--shard", "slurm", env=env)
    check("--shard slurm is shard 1/3", r.returncode == 0 and
          json.load(open(os.path.join(sl, "study.json")))["shard"]["index"] == 1, r.stderr)

    for value in ["3/3", "a/b", "1", "-1/2", "1/0", "slurm", "2/1000001"]:
        env = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}
        r = run("sweep", scene, "--out", os.path.join(d, "bad"), "--no-report", "--shard", value,
                env=env)
        check(f"--shard {value}: exit 2", one_error(r, 2, ["--shard"]), r.stderr)

print(f"shards: {len(failures)} failed")
sys.exit(1 if failures else 0)
