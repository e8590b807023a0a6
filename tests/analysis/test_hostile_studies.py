#!/usr/bin/python3
"""ctest: studies under kills, edits and hostile directories, one class per ctest
(docs/testing.md "What pgt promises"): rows land per case, merge never loses a finished
study, shards are checked against their plan, clusters' task ids map to shards. Arguments:
PGT_BINARY SOURCE_DIR CLASS."""
import csv
import fcntl
import io
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


def _no_gl(name, r):
    """Whether `r` failed for want of a GL (the check is then skipped, as gl_texture_limit
    skips)."""
    if r.returncode != 0 and ("no GL" in r.stderr or "EGL" in r.stderr):
        print(f"skipped {name}: no GL here:", r.stderr.strip())
        return True
    return False


INT_SHADER = ("uniform sampler2D depthMap;\nuniform int uMaxLayers;\nuniform float k;\n"
              "vec2 F(vec2 uv, vec3 V) {\n"
              "    return uv - V.xy / V.z * k * texture(depthMap, uv).r * float(uMaxLayers);\n}\n")


def _int_uniforms(d):
    """An int uniform is a 32-bit int: 3e9, 2^53, -3e9 and 2^64 - 1 written as integers (in
    the method entry, a preset's uniforms, a sweep's list alike; pgt.render's dict in
    tests/python) are exit 2 naming methods[i].uniforms.NAME, the value and the range, before
    any GL; 2^31 - 1 still renders."""
    shader = write(d, "int.glsl", INT_SHADER)
    out = os.path.join(d, "int_out")
    for value in (3000000000, 2**53, -3000000000, 2**64 - 1):
        scene = copy(GOOD)
        scene["methods"] = ["parallax", {"name": "mine", "glsl": shader, "function": "F",
                                         "uniforms": {"uMaxLayers": value, "k": 0.0}}]
        path = write(d, "int.json", json.dumps(scene))
        expect_error(f"int uniform {value}", run(["render", path, "--out", out]), 2,
                     [path, f"methods[1].uniforms.uMaxLayers = {value}", "2147483647"], out)
    scene = copy(GOOD)
    scene["methods"] = [{"preset": "bevy_relief", "uniforms": {"max_steps": 3000000000}}]
    path = write(d, "preset.json", json.dumps(scene))
    expect_error("a preset's int uniform 3e9", run(["render", path, "--out", out]), 2,
                 [path, "methods[0].uniforms.max_steps = 3000000000", "2147483647"], out)
    scene = copy(SWEEP)
    scene["methods"] = [{"name": "mine", "glsl": shader, "function": "F",
                         "uniforms": {"uMaxLayers": 1, "k": 0.0}}]
    scene["sweep"]["mine.uniforms.uMaxLayers"] = [8, 2**53]
    path = write(d, "int_sweep.json", json.dumps(scene))
    expect_error("a swept int uniform 2^53", sweep(path, out), 2,
                 [path, f"sweep.mine.uniforms.uMaxLayers = {2**53}", "2147483647"], out)
    scene = copy(GOOD)
    scene["methods"] = [{"name": "mine", "glsl": shader, "function": "F",
                         "uniforms": {"uMaxLayers": 2147483647, "k": 0.0}}]
    path = write(d, "int_max.json", json.dumps(scene))
    r = run(["render", path, "--out", out])
    if not _no_gl("int uniform 2^31 - 1", r):
        check("int uniform 2^31 - 1 renders", r.returncode == 0, r.stderr)


def _csv_edit(column, value, row=0):
    """An edit of results.csv's lines: row `row`'s `column` set to `value` (a real CSV
    reader: the params column holds commas)."""
    def edit(lines):
        records = list(csv.reader([l for l in lines if l]))
        records[1 + row][records[0].index(column)] = value
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(records)
        return buf.getvalue().split("\n")
    return edit


def _merge_light_columns(d):
    """A shard's hand-edited light_theta / light_phi is checked against the case's planned
    light as theta..bias_ratio are: a value of no case, or another case's, is exit 2 naming
    the shard's results.csv, the line and the column."""
    scene = copy(SWEEP)
    scene["light"] = {"theta": 45, "phi": 90}
    scene["sweep"].update(theta=[0, 40], light_theta=[20, 60], light_phi=[0, 90])
    _, dirs = shards_of(d, scene, 2, "light")
    first = rows_of(os.path.join(dirs[0], "results.csv"))[0]
    check("case 0's planned light", (first["light_theta"], first["light_phi"]) == ("20", "0"),
          f"{first['light_theta']}, {first['light_phi']}")
    for column, value in [("light_theta", "21"), ("light_theta", "60"), ("light_phi", "45"),
                          ("light_phi", "90"), ("light_theta", "nan")]:
        name = f"{column}_{value}"
        copies = edited(d, dirs, name, edit_csv=_csv_edit(column, value))
        out = os.path.join(d, "light_out")
        expect_error(f"edited {column} {value}", merge(copies, out), 2,
                     ["results.csv", f"line 2: {column} = {value}", "case 0 has"], out)
    r = merge(dirs, os.path.join(d, "merged"))
    check("the unedited light shards merge", r.returncode == 0, r.stderr)


def _repeated_values(d):
    """A value listed twice, or two that print alike in results.csv (9 significant digits,
    a case's key), would make two cases of one key: exit 2 naming sweep.LIST and the value;
    as does a method list's value giving an earlier one's configuration or label."""
    shader = write(d, "float.glsl", INT_SHADER)
    base = copy(SWEEP)
    base["light"] = {"theta": 45, "phi": 90}
    base["methods"].append({"name": "mine", "glsl": shader, "function": "F",
                            "uniforms": {"uMaxLayers": 1, "k": 0.5}})
    out = os.path.join(d, "repeated_out")
    lists = [("theta", [30, 30], "30"), ("theta", [45, 45.0000000001], "45.0000000001"),
             ("theta", {"from": 80, "to": 80.00000001, "step": 1e-9}, "sweep.theta"),
             ("phi", [0, 0.0], "0.0"), ("scale", [0.05, 0.02, 0.05000000001], "0.05000000001"),
             ("bias_ratio", [0, -0.5, -0.5], "-0.5"), ("bias", [-0.01, -0.01], "-0.01"),
             ("light_theta", [45, 45], "45"), ("light_phi", [90, 90.00000000001], "90.00000000001"),
             ("pom.max_layers", [8, 16, 8], "8"), ("pom.max_layers", [8, 8.0], "8.0"),
             ("mine.uniforms.k", [0.5, 0.5], "0.5"),
             ("mine.uniforms.k", [0.5, 0.5000000001], "0.5000000001"),
             ("mine.uniforms.uMaxLayers", [2, 2], "2")]
    for key, values, shown in lists:
        scene = copy(base)
        scene["sweep"][key] = values
        path = write(d, "repeated.json", json.dumps(scene))
        expect_error(f"sweep.{key} = {values}", sweep(path, out), 2,
                     [path, f"sweep.{key}", shown, "once"], out)


def _resume_equals_whole(d):
    """Distinct values that are close (45, 45.001) and a zero scale with several b/s (every
    ratio gives b = 0 there) are cases of their own: the study runs, and one stopped after
    K cases (--max-cases) or SIGKILLed, then resumed, equals the uninterrupted run row for
    row, each case once."""
    scene = copy(SWEEP)
    scene["heightmap"]["size"] = [32, 32]
    scene["camera"]["resolution"] = [48, 48]
    scene["light"] = {"theta": 45, "phi": 90}
    scene["truth"] = {"rate": 2}
    scene["sweep"] = {"theta": [0, 45, 45.001], "scale": [0, 0.05],
                      "bias_ratio": [0, -0.5, -1], "light_theta": [30, 30.0001],
                      "timing": {"repeats": 1, "fragments": 64}}
    path = write(d, "distinct.json", json.dumps(scene))
    whole = os.path.join(d, "whole")
    r = sweep(path, whole)
    check("distinct close values run", r.returncode == 0, r.stderr)
    want = key_rows(os.path.join(whole, "results.csv"))
    pairs = {(x["case"], x["label"]) for x in rows_of(os.path.join(whole, "results.csv"))}
    check("one row per case and method", len(want) == 36 * 2 and len(pairs) == 36 * 2,
          f"{len(want)} rows")
    stopped = os.path.join(d, "stopped")
    for k in (7, 6, 12):  # the first surfaces (s = 0) end part-way
        r = sweep(path, stopped, "--max-cases", str(k))
        check(f"--max-cases {k}", r.returncode == 0, r.stderr)
    r = sweep(path, stopped)
    check("resumed after --max-cases", r.returncode == 0 and "resumed" in r.stdout, r.stderr)
    check("resumed after --max-cases equals uninterrupted",
          key_rows(os.path.join(stopped, "results.csv")) == want)
    killed = os.path.join(d, "killed")
    csv_path = os.path.join(killed, "results.csv")
    p = subprocess.Popen([PGT, "sweep", path, "--out", killed, "--no-report"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while time.time() < deadline and p.poll() is None:
        if os.path.exists(csv_path) and sum(1 for _ in open(csv_path)) > 1 + 2 * 3:
            break
        time.sleep(0.005)
    p.send_signal(signal.SIGKILL)
    p.wait()
    r = sweep(path, killed)
    check("resumed after SIGKILL", r.returncode == 0, r.stderr)
    check("resumed after SIGKILL equals uninterrupted", key_rows(csv_path) == want)


def _long_labels(d):
    """A uniform sweep's generated label (label, uniform name and value) over 200 bytes is cut
    to 200 with 8 hex digits of its SHA-1: --images writes LABEL_error.png (a label of 249
    bytes made a 259-byte name: exit 3), the labels differ, and a second run makes the same."""
    name = "u" + "x" * 239
    shader = write(d, "long.glsl", "uniform sampler2D depthMap;\nuniform float " + name + ";\n"
                   "vec2 F(vec2 uv, vec3 V) {\n    return uv - V.xy / V.z * " + name +
                   " * texture(depthMap, uv).r;\n}\n")
    scene = copy(SWEEP)
    scene["methods"] = ["parallax", {"name": "mine", "glsl": shader, "function": "F",
                                     "uniforms": {name: 0.02}}]
    scene["sweep"] = {"theta": [0, 40], "scale": [0.05], f"mine.uniforms.{name}": [0.02, 0.05],
                      "timing": {"repeats": 1, "fragments": 16}}
    path = write(d, "long.json", json.dumps(scene))
    labels = []
    for out in (os.path.join(d, "long_a"), os.path.join(d, "long_b")):
        r = sweep(path, out, "--images")
        if _no_gl("long labels", r):
            return
        check("long labels: sweep --images", r.returncode == 0, r.stderr)
        if r.returncode != 0:
            return
        labels.append(sorted({x["label"] for x in rows_of(os.path.join(out, "results.csv"))}))
        names = [f for _, _, files in os.walk(out) for f in files]
        check("file names within 255 bytes", max(len(f.encode()) for f in names) <= 255,
              max(names, key=len))
    mine = [x for x in labels[0] if x.startswith("mine_")]
    check("two labels of 200 bytes, cut with a hash", len(mine) == 2 and
          all(len(x) == 200 and x.startswith("mine_" + name[:100]) for x in mine) and
          mine[0][:191] == mine[1][:191] and mine[0] != mine[1], f"{mine}")
    check("the same labels again", labels[0] == labels[1], f"{labels}")
    r = sweep(path, os.path.join(d, "long_a"), "--images")
    check("long labels: resumed complete", r.returncode == 0 and "resumed" in r.stdout, r.stderr)


def study_hostile3(d):
    """An outside tester's third round: int uniforms beyond 32 bits, merged shards with edited
    light angles, sweep lists with a value twice (or two that print alike), and uniform
    sweeps whose generated labels made file names over 255 bytes."""
    _int_uniforms(d)
    _merge_light_columns(d)
    _repeated_values(d)
    _resume_equals_whole(d)
    _long_labels(d)


def _edited_includes(d):
    """A file a method includes is part of the study: run one case of a study whose HLSL (or
    GLSL) method includes lib, edit lib, resume: refused (exit 2, naming the study), rows kept;
    shards run before and after the edit do not merge."""
    for kind, lib, main_text, call in (
            ("hlsl", "float k() { return 1.0; }\n",
             '#include "lib.hlsli"\nfloat2 F(float2 uv, float3 V, float s) '
             "{ return uv + V.xy * s * k(); }\n", "F(uv, V, s)"),
            ("glsl", "float k() { return 1.0; }\n",
             '#include "lib.glsli"\nvec2 F(vec2 uv, vec3 V, float s) '
             "{ return uv + V.xy * s * k(); }\n", "F(uv, V, s)")):
        sub = os.path.join(d, kind)
        os.makedirs(sub)
        lib_path = write(sub, f"lib.{kind}i", lib)
        write(sub, f"main.{kind}", main_text)
        scene = copy(SWEEP)
        scene["methods"] = ["parallax", {"name": "mine", kind: f"main.{kind}", "call": call,
                                         "sampler": ""}]
        path = write(sub, "scene.json", json.dumps(scene))
        part = os.path.join(sub, "part")
        check(f"{kind}: one case", sweep(path, part, "--max-cases", "1").returncode == 0)
        _, before = shards_of(sub, scene, 2, name="before")
        write(sub, f"lib.{kind}i", lib.replace("1.0", "0.5"))
        kept = open(os.path.join(part, "results.csv")).read()
        r = sweep(path, part)
        check(f"{kind}: an edited include is another study", r.returncode == 2 and
              "study.json" in r.stderr and "--fresh" in r.stderr, f"exit {r.returncode} {r.stderr}")
        check(f"{kind}: rows kept", open(os.path.join(part, "results.csv")).read() == kept)
        _, after = shards_of(sub, scene, 2, name="after")
        out = os.path.join(sub, "merged")
        r = merge([before[0], after[1]], out)
        check(f"{kind}: shards before and after the edit do not merge", r.returncode == 2 and
              not os.path.exists(out), f"exit {r.returncode} {r.stderr}")
        check(f"{kind}: lib is read", os.path.exists(lib_path))


def _edited_rows_resume(d):
    """Resume checks each row as merge does: after --max-cases 1, a row's params edited or
    emptied, its method or label changed, its theta moved: resume is exit 2 naming
    results.csv, the line and the field, and results.csv is left as it was."""
    scene = copy(SWEEP)
    scene["methods"] = ["parallax", {"name": "pom", "min_layers": 4, "max_layers": 8,
                                     "format": "unorm8"}]
    path = write(d, "rows.json", json.dumps(scene))
    whole = os.path.join(d, "rows_whole")
    check("rows: one case", sweep(path, whole, "--max-cases", "1").returncode == 0)
    rows = rows_of(os.path.join(whole, "results.csv"))  # parallax, then pom
    check("rows: pom reads unorm8", "unorm8" in rows[1]["params"], rows[1]["params"])
    edits = [("params", rows[1]["params"].replace("unorm8", "unorm16"), 1), ("params", "", 1),
             ("params", "{}", 0), ("method", "parallax", 1), ("label", "relief", 0),
             ("theta", "20", 1), ("scale", "0.03", 0)]
    for column, value, row in edits:
        work = os.path.join(d, f"rows_{column}_{row}_{len(value)}")
        shutil.copytree(whole, work)
        _edit_file(os.path.join(work, "results.csv"), _csv_edit(column, value, row))
        kept = open(os.path.join(work, "results.csv")).read()
        r = sweep(path, work)
        expect_error(f"resume refuses an edited {column}", r, 2,
                     ["results.csv", f"line {row + 2}: {column}", "--fresh"])
        check(f"{column}: results.csv as it was",
              open(os.path.join(work, "results.csv")).read() == kept)


def study_hostile4(d):
    """An outside tester's fourth round: a study's identity covers the files its methods
    include (HLSL as GLSL); a resume checks each row as a merge does."""
    _edited_includes(d)
    _edited_rows_resume(d)


def _columns_moved(extra=None, drop=None):
    """An edit of results.csv's lines: its columns in reverse order, `extra` (a value) in a
    column "note" at the third place, or without the column `drop`."""
    def edit(lines):
        records = list(csv.reader([l for l in lines if l]))
        names = [n for n in reversed(records[0]) if n != drop]
        out = []
        for r in records:
            row = dict(zip(records[0], r))
            moved = [row[n] for n in names]
            if extra is not None:
                moved.insert(2, "note" if r is records[0] else extra)
            out.append(moved)
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(out)
        return buf.getvalue().split("\n")
    return edit


def _edit_file(path, edit):
    lines = open(path).read().split("\n")
    open(path, "w").write("\n".join(edit(lines)))


def csv_by_name(d):
    """results.csv's columns are read by name: a study whose results.csv has its columns in
    another order, or a column pgt does not write, resumes (rewritten as pgt writes it, the
    other column left out with a note) and merges as the unedited one does; an edited value is
    still named by its column; a missing column is exit 2 naming the file and the column."""
    path = write(d, "study.json", json.dumps(SWEEP))
    whole = os.path.join(d, "whole")
    check("uninterrupted", sweep(path, whole).returncode == 0)
    want = key_rows(os.path.join(whole, "results.csv"))
    header = open(os.path.join(whole, "results.csv")).readline()
    part = os.path.join(d, "part")
    part_csv = os.path.join(part, "results.csv")
    check("3 cases", sweep(path, part, "--max-cases", "3").returncode == 0)
    _edit_file(part_csv, _columns_moved(extra='a, "b"'))
    r = sweep(path, part)
    check("moved columns resume", r.returncode == 0 and "3 resumed" in r.stdout,
          r.stdout + r.stderr)
    check("the unknown column noted", "note" in r.stderr and "left out" in r.stderr, r.stderr)
    check("resumed equals uninterrupted", key_rows(part_csv) == want)
    check("rewritten as pgt writes it", open(part_csv).readline() == header)
    _, dirs = shards_of(d, SWEEP, 2)
    plain = os.path.join(d, "plain")
    check("merge", merge(dirs, plain).returncode == 0)
    copies = edited(d, dirs, "moved", edit_csv=_columns_moved(extra="x"))
    moved = os.path.join(d, "merged_moved")
    r = merge(copies, moved)
    check("moved columns merge", r.returncode == 0 and "note" in r.stderr, r.stderr)
    check("merged as the unedited shards", r.returncode == 0 and
          open(os.path.join(moved, "results.csv")).read() ==
          open(os.path.join(plain, "results.csv")).read())
    check("merged equals uninterrupted", key_rows(os.path.join(plain, "results.csv")) == want)
    for column, value in [("theta", "21"), ("label", "parallaxX"), ("light_phi", "45")]:
        copies = edited(d, dirs, f"moved_{column}", edit_csv=lambda lines, c=column, v=value:
                        _csv_edit(c, v)(_columns_moved()(lines)))
        out = os.path.join(d, "out")
        expect_error(f"moved columns, edited {column}", merge(copies, out), 2,
                     ["results.csv", f"line 2: {column} = {value}"], out)
    copies = edited(d, dirs, "no_depth", edit_csv=_columns_moved(drop="depth_mean"))
    expect_error("a shard without depth_mean", merge(copies, os.path.join(d, "out")), 2,
                 [copies[0], "results.csv", "depth_mean"], os.path.join(d, "out"))
    _edit_file(part_csv, _columns_moved(drop="depth_mean"))
    kept = open(part_csv).read()
    expect_error("resuming without depth_mean", sweep(path, part), 2,
                 [part_csv, "depth_mean", "--fresh"])
    check("results.csv unchanged", open(part_csv).read() == kept)


if __name__ == "__main__":
    main([rows_per_case, merge_data_loss, merge_edited_shards, merge_memory, slurm_semantics,
          small_options, study_hostile3, study_hostile4, csv_by_name])
