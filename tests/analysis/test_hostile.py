#!/usr/bin/python3
"""ctest: hostile, broken and concurrent input through the real CLI, one class per ctest
(docs/testing.md "What pgt promises"). Each class holds the cases an outside tester found: pgt must
exit with the documented status (2 bad input, 3 output not writable), print one error line
naming the file and field, never crash or hang, and never mix, duplicate or half-write
results. Arguments: PGT_BINARY SOURCE_DIR CLASS."""
import fcntl
import json
import os
import resource
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_common import *  # noqa: E402,F401,F403  (the harness: run, check, scenes, ...)


# ---------------------------------------------------------------------------------------------
def deep_json(d):
    """Nesting bounded at parse time (64 levels): never a stack overflow."""
    deep = "[" * 100000 + "]" * 100000
    for where, text in [("root", deep),
                        ("description", json.dumps(GOOD)[:-1] + ', "description": ' + deep + "}"),
                        ("methods", json.dumps(GOOD).replace('["parallax"]', deep)),
                        ("sweep list", json.dumps(GOOD)[:-1] + ', "sweep": {"theta": ' + deep + "}}")]:
        path = write(d, "deep.json", text)
        out = os.path.join(d, "out")
        expect_error(f"deep {where}", run(["render", path, "--out", out]), 2,
                     ["deep.json", "nested deeper than 64"], out)
    nested = copy(GOOD)
    nested["description"] = json.loads("[" * 60 + "]" * 60)  # within the bound: parsed,
    path = write(d, "ok.json", json.dumps(nested))           # then refused by its type
    expect_error("60 levels parsed", run(["render", path, "--out", os.path.join(d, "ok")]), 2,
                 ["description", "expected a string"])
    # A map wide enough that the truth lattice passes OpenSubdiv's largest tessellation rate
    # (32767) renders: it was an internal check failure.
    wide = copy(GOOD)
    wide["heightmap"] = {"procedural": "constant", "size": [20000, 2]}
    path = write(d, "wide.json", json.dumps(wide))
    r = run(["render", path, "--out", os.path.join(d, "wide")])
    check("20000-texel map renders", r.returncode == 0, r.stderr)


def obj_indices(d):
    """Every OBJ index and coordinate is validated: no crash inside OpenSubdiv, no read
    outside the UV array, no nan read as 0."""
    head = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    bad = {"face index 99": head + "f 1/1 2/2 99/3 4/4\n",
           "relative -50": head + "f -50/1 2/2 3/3 4/4\n",
           "relative -1e8": head + "f -100000000/1 2/2 3/3 4/4\n",
           "vt index 2e9": head + "f 1/2000000000 2/2 3/3 4/4\n",
           "vt index 99": head + "f 1/1 2/2 3/99 4/4\n",
           "nan position": head.replace("v 1 1 0", "v nan 1 0") + "f 1/1 2/2 3/3 4/4\n",
           "inf uv": head.replace("vt 1 1", "vt inf 1") + "f 1/1 2/2 3/3 4/4\n"}
    for name, text in bad.items():
        write(d, "mesh.obj", text)
        scene = copy(GOOD)
        scene["base"] = {"type": "mesh", "file": "mesh.obj", "refine": 1}
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        expect_error(f"OBJ {name}", run(["render", path, "--out", out]), 2,
                     ["scene.json", "base.file", "mesh.obj"], out)
    write(d, "mesh.obj", head + "f 1/1 2/2 3/3 4/4\n")  # the same quad, valid: renders
    r = run(["render", path, "--out", os.path.join(d, "ok")])
    check("valid OBJ", r.returncode == 0, r.stderr)


def shell_injection(d):
    """The report is started with an argument vector: quotes in --out are a path, not shell."""
    scene = copy(SWEEP)
    scene["sweep"] = {"theta": [0, 30], "timing": {"repeats": 1, "fragments": 16}}
    path = write(d, "scene.json", json.dumps(scene))
    marker = os.path.join(d, "PWNED")
    hostile = os.path.join(d, f"x';touch {marker};'")
    r = run(["sweep", path, "--out", hostile], timeout=300)
    check("no command ran", not os.path.exists(marker), r.stdout + r.stderr)
    check("hostile --out works", r.returncode == 0, r.stderr)
    quoted = os.path.join(d, "it's")
    r = run(["sweep", path, "--out", quoted], timeout=300)
    check("--out it's", r.returncode == 0 and os.path.exists(os.path.join(quoted, "results.csv")),
          r.stderr)
    has_matplotlib = subprocess.run(["/usr/bin/python3", "-c", "import matplotlib, pandas"],
                                    capture_output=True).returncode == 0
    if has_matplotlib:
        check("report in it's", os.path.exists(os.path.join(quoted, "report.md")), r.stdout)


def gl_texture_limit(d):
    """A map the GL cannot hold is named before any upload (not blamed on a uniform)."""
    for method in [{"preset": "godot"},
                   {"name": "mine", "glsl": "pgt:parallax.glsl",
                    "function": "ParallaxMapping", "sampler": "heightMap",
                    "uniforms": {"height_scale": "scale", "height_bias": "bias"}}]:
        scene = copy(GOOD)
        scene["heightmap"] = {"procedural": "constant", "size": [20000, 2]}
        scene["methods"] = [method]
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        r = run(["render", path, "--out", out])
        if "no GL" in r.stderr or "EGL" in r.stderr:
            print("skipped GL limit check: no GL here:", r.stderr.strip())
            return
        expect_error(f"GL limit {list(method.values())[0]}", r, 2,
                     ["20000x2", "GL_MAX_TEXTURE_SIZE", "sampler"])
        check("not blamed on a uniform", "uniforms." not in r.stderr, r.stderr)


def concurrent_sweeps(d):
    """A study directory is locked: a second sweep into it is refused while one runs, so no
    row is ever written twice."""
    path = write(d, "scene.json", json.dumps(SWEEP))
    out = os.path.join(d, "held")
    os.makedirs(out)
    with open(os.path.join(out, ".pgt-lock"), "w") as held:  # as a running sweep holds it
        fcntl.flock(held, fcntl.LOCK_EX)
        expect_error("refused while locked", sweep(path, out), 3, ["in use by another pgt sweep"])
    r = sweep(path, out)  # released (a killed run's lock goes with its process): runs
    check("runs once released", r.returncode == 0 and "8 cases run" in r.stdout, r.stderr)
    # Two real runs started together: one does the study, the other is refused or, if it
    # started after the first ended, resumes everything; never a row twice.
    slow = copy(SWEEP)
    slow["heightmap"]["size"] = [64, 64]
    slow["camera"]["resolution"] = [128, 128]
    slow["sweep"]["theta"] = list(range(0, 90, 2))
    slow["truth"]["rate"] = 4
    path = write(d, "slow.json", json.dumps(slow))
    out = os.path.join(d, "study")
    runs = [subprocess.Popen([PGT, "sweep", path, "--out", out, "--no-report"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for _ in range(2)]
    results = [(p.communicate(timeout=600), p.returncode) for p in runs]
    codes = sorted(code for _, code in results)
    check("one runs, one refused", codes in ([0, 3], [0, 0]), f"{results}")
    if codes == [0, 3]:
        refused = [err for (out_, err), code in results if code == 3][0]
        check("refusal message", "in use by another pgt sweep" in refused, refused)
    keys = [(r["case"], r["label"]) for r in rows_of(os.path.join(out, "results.csv"))]
    check("no duplicate rows", len(keys) == len(set(keys)) == 90 * 2, f"{len(keys)} rows")


def study_identity(d):
    """Every input that changes a number is in the study's identity: an edit is refused,
    never resumed into the old rows."""
    write(d, "map.png", png(4, 4, [[0, 64, 128, 255]] * 4))
    write(d, "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
          "f 1/1 2/2 3/3 4/4\n")
    edits = {
        "procedural seed": (SWEEP, lambda s: s["heightmap"].update(seed=4)),
        "procedural jitter": (SWEEP, lambda s: s["heightmap"].update(jitter=0.5)),
        "camera target": (SWEEP, lambda s: s["camera"].update(target=[0.1, 0, 0])),
        "png content": ({**copy(SWEEP), "heightmap": {"file": "map.png"}},
                        lambda s: write(d, "map.png", png(4, 4, [[0, 64, 128, 254]] * 4))),
        "obj content": ({**copy(SWEEP), "base": {"type": "mesh", "file": "quad.obj", "refine": 1},
                         "camera": {"type": "orthographic", "theta": 30, "resolution": [16, 16]}},
                        lambda s: write(d, "quad.obj", open(os.path.join(d, "quad.obj")).read()
                                        .replace("v 1 1 0", "v 1 1 0.1"))),
    }
    for name, (base, edit) in edits.items():
        scene = copy(base)
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "study_" + name.replace(" ", "_"))
        r = sweep(path, out, "--max-cases", "3")
        check(f"{name}: first part", r.returncode == 0, r.stderr)
        edit(scene)
        write(d, "scene.json", json.dumps(scene))
        expect_error(f"{name}: edited study refused", sweep(path, out), 2,
                     ["different study"])
    # A description is not an input: editing it resumes.
    scene = copy(SWEEP)
    path = write(d, "scene.json", json.dumps(scene))
    out = os.path.join(d, "study_description")
    sweep(path, out, "--max-cases", "3")
    scene["description"] = "edited"
    write(d, "scene.json", json.dumps(scene))
    r = sweep(path, out)
    check("description edit resumes", r.returncode == 0 and "3 resumed" in r.stdout, r.stderr)


def results_csv_state(d):
    """A 0-byte results.csv gets its header; a results.csv that is a directory is an output
    error; a resumed study equals a fresh one."""
    path = write(d, "scene.json", json.dumps(SWEEP))
    fresh = os.path.join(d, "fresh")
    check("fresh", sweep(path, fresh).returncode == 0)
    empty = os.path.join(d, "empty")
    os.makedirs(empty)
    write(empty, "results.csv", "")
    r = sweep(path, empty)
    check("0-byte results.csv", r.returncode == 0 and
          key_rows(os.path.join(empty, "results.csv")) == key_rows(os.path.join(fresh, "results.csv")),
          r.stderr)
    r = sweep(path, empty)
    check("then resumes", r.returncode == 0 and "8 resumed" in r.stdout, r.stderr)
    isdir = os.path.join(d, "isdir")
    os.makedirs(os.path.join(isdir, "results.csv"))
    expect_error("results.csv a directory", sweep(path, isdir), 3, ["results.csv", "not a regular file"])


def labels(d):
    """Labels are checked up front (unique, safe characters, length); CSV is quoted."""
    bad = {"duplicate": [{"name": "parallax", "label": "a"}, {"name": "pom", "label": "a"}],
           "300 characters": [{"name": "parallax", "label": "x" * 300}],
           "comma": [{"name": "parallax", "label": "a,b"}],
           "quote": [{"name": "parallax", "label": 'a"b'}],
           "newline": [{"name": "parallax", "label": "a\nb"}],
           "preset label": [{"preset": "godot", "label": "../x"}]}
    for name, methods in bad.items():
        scene = copy(GOOD)
        scene["methods"] = methods
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        expect_error(f"label {name}", run(["render", path, "--out", out]), 2,
                     ["scene.json", ".label"], out)
    # A generated label never collides with a user's: "parallax_2" is taken, the second
    # unlabelled parallax gets another one.
    scene = copy(GOOD)
    scene["methods"] = ["parallax", {"name": "parallax", "label": "parallax_2"}, "parallax"]
    path = write(d, "scene.json", json.dumps(scene))
    out = os.path.join(d, "gen")
    r = run(["render", path, "--out", out])
    got = [m["label"] for m in json.load(open(os.path.join(out, "summary.json")))["methods"]] \
        if r.returncode == 0 else []
    check("generated labels unique", r.returncode == 0 and len(set(got)) == 3, f"{got} {r.stderr}")
    # stress.csv names scenes by file stem: a comma in it is quoted, not a new column.
    path = write(d, "a,b.json", json.dumps(GOOD))
    out = os.path.join(d, "stress")
    r = run(["stress", path, "--out", out])
    got = rows_of(os.path.join(out, "stress.csv")) if r.returncode == 0 else []
    check("stress.csv quotes a scene name", [x["scene"] for x in got] == ["a,b"],
          f"{got[:1]} {r.stderr}")
    # Resume works with quoted fields (the params column): nothing recomputed.
    path = write(d, "sweep.json", json.dumps(SWEEP))
    out = os.path.join(d, "study")
    sweep(path, out)
    r = sweep(path, out)
    check("quoted CSV resumes", r.returncode == 0 and "0 cases run, 8 resumed" in r.stdout, r.stdout)


def full_disk(d):
    """A write that fails (file size limit: EFBIG, as a full disk's ENOSPC) exits 3 and
    leaves no output file behind, neither empty nor partial."""
    path = write(d, "scene.json", json.dumps(GOOD))

    def limit(size):
        def pre():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
        return pre
    # 8 x 8 outputs: frame.exr about 1.2 KB, the error map about 5 KB, summary.json 4 KB.
    for size in [0, 1000, 3000]:
        out = os.path.join(d, f"out_{size}")
        os.makedirs(out)
        r = subprocess.run([PGT, "render", path, "--out", out], capture_output=True, text=True,
                           preexec_fn=limit(size), timeout=120)
        left = sorted(os.listdir(out))
        check(f"limit {size}: exit 3", r.returncode == 3 and "cannot" in r.stderr,
              f"exit {r.returncode} {r.stderr!r}")
        check(f"limit {size}: nothing left", left == [], f"left {left}")
    # A study with --images whose frames cannot be written: exit 3, no empty case folder.
    scene = copy(SWEEP)
    scene["camera"]["resolution"] = [48, 48]
    study = write(d, "study.json", json.dumps(scene))
    out = os.path.join(d, "study_out")
    r = subprocess.run([PGT, "sweep", study, "--out", out, "--images", "--no-report"],
                       capture_output=True, text=True, preexec_fn=limit(6000), timeout=300)
    images = os.path.join(out, "images")
    empty = [n for n in (os.listdir(images) if os.path.isdir(images) else [])
             if not os.listdir(os.path.join(images, n))]
    check("sweep --images, frames too large: exit 3", r.returncode == 3, f"exit {r.returncode}")
    check("sweep --images: no empty case folder", empty == [], f"{empty}")


def render_checks_out_first(d):
    """An unwritable --out fails before any rendering (not after it). The witness: a GL
    device that does not exist is only found when a GLSL method first runs, so an output
    error (3) instead of that GL error (2) means nothing was rendered first."""
    scene = copy(GOOD)
    scene["methods"] = [{"preset": "godot"}]
    path = write(d, "scene.json", json.dumps(scene))
    blocker = write(d, "file", "x")
    r = run(["render", path, "--out", os.path.join(blocker, "sub"), "--gl-device", "egl-device:99"])
    expect_error("unwritable --out, before the render", r, 3, ["cannot"])
    for command in ["fit"]:
        r = run([command, path, "--out", os.path.join(blocker, "sub")])
        expect_error(f"{command}: unwritable --out", r, 3, ["cannot"])


def outputs_whole(d):
    """One render's files replace the earlier ones as a set or not at all: with a directory
    where summary.json goes, a second render into the same folder is exit 3 naming it, and
    every file of the first render is still the first render's (no frame.exr of the second,
    no error map of a method only the second has), with no temporary left."""
    out = os.path.join(d, "out")
    first = copy(GOOD)
    first["methods"] = ["parallax", "pom"]
    r = run(["render", write(d, "a.json", json.dumps(first)), "--out", out])
    check("first render", r.returncode == 0, r.stderr)
    before = {n: open(os.path.join(out, n), "rb").read() for n in os.listdir(out)}
    os.remove(os.path.join(out, "summary.json"))
    os.mkdir(os.path.join(out, "summary.json"))
    second = copy(GOOD)
    second["methods"] = ["relief"]
    second["camera"]["theta"] = 50
    r = run(["render", write(d, "b.json", json.dumps(second)), "--out", out])
    expect_error("a directory in the way", r, 3, ["summary.json", "directory"])
    after = sorted(os.listdir(out))
    check("nothing of the second render", after == sorted(before), f"{after}")
    for name, data in before.items():
        if name != "summary.json":
            check(f"{name} is the first render's", open(os.path.join(out, name), "rb").read()
                  == data)


def memory_estimates(d):
    """Inputs accepted as valid but too large are refused with the estimate, before any
    allocation; --memory-limit raises or lowers the limit."""
    cases = {
        "noise 4096 x 12 octaves": (["heightmap"], {"procedural": "noise", "size": [32, 32],
                                                     "frequency": 4096, "octaves": 12},
                                    "heightmap.octaves"),
        "noise 64 x 12 octaves": (["heightmap"], {"procedural": "noise", "size": [32, 32],
                                                   "frequency": 64, "octaves": 12},
                                  "heightmap.octaves"),
    }
    for name, (keys, value, field) in cases.items():
        scene = copy(GOOD)
        node = scene
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        r = run(["render", path, "--out", out])
        expect_error(name, r, 2, [field, "needs about", "MB", "--memory-limit"], out)
    # Frames stream in bands; what stays is about 8 bytes a pixel per method (its coded errors,
    # the sorted copy): 8192^2 (the largest frame) with 100 methods is far beyond the limit.
    scene = copy(GOOD)
    scene["camera"]["resolution"] = [8192, 8192]
    scene["methods"] = [{"name": "parallax", "label": f"p{k}"} for k in range(100)]
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("8192^2 frame, 100 methods", run(["render", path, "--out", os.path.join(d, "f")]),
                 2, ["camera.resolution", "needs about", "MB", "--memory-limit"], os.path.join(d, "f"))
    # A 2^20-quad OBJ at refine 2 is estimated from its face count, before refining.
    scene = copy(GOOD)
    scene["base"] = {"type": "mesh", "cage": "torus", "segments": [1024, 1024], "refine": 2}
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("1M-quad mesh at refine 2", run(["render", path, "--out", os.path.join(d, "o")]),
                 2, ["base.refine", "needs about"])
    # A sweep of 10,001^3 values: refused before the case list is built.
    scene = copy(SWEEP)
    scene["sweep"] = {"theta": {"from": 0, "to": 90, "step": 0.009}, "scale": {"from": 0, "to": 1, "step": 0.0001},
                      "bias": {"from": 0, "to": 1, "step": 0.0001}}
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("10001^3 cases", sweep(path, os.path.join(d, "s")), 2, ["sweep", "cases"])
    # The limit is an option: a frame within the default is refused under 64 MB.
    scene = copy(GOOD)
    scene["camera"]["resolution"] = [2048, 2048]
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("2048^2 under 64 MB", run(["render", path, "--out", os.path.join(d, "m"),
                                            "--memory-limit", "64"]), 2, ["limit of 64 MB"])
    expect_error("bad --memory-limit", run(["render", path, "--out", os.path.join(d, "m"),
                                            "--memory-limit", "lots"]), 2, ["--memory-limit"])


def memory_beyond_the_frame(d):
    """--memory-limit holds beyond the frame: a plane's truth that no split into blocks brings
    under the budget, the maps the methods read (derived, pyramid, cone) and the procedural
    map itself are estimated and refused before they are made, and the process stays far
    below what building them would take (a 4096^2 map's truth: about 10 GB)."""
    big = copy(GOOD)
    big["heightmap"] = {"procedural": "sine", "size": [4096, 4096]}
    big["base"] = {"type": "plane", "infinite": True}
    big["camera"] = {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [64, 64]}
    big["truth"] = {"rate": 2, "memory_mb": 32}
    cases = [("truth in no blocks", big, "100", "truth.memory_mb"),
             ("cone map", {**copy(big), "methods": ["cone"], "truth": {"rate": 1}}, "400",
              "camera.resolution"),
             ("derived maps", {**copy(big), "methods": ["iterative"], "truth": {"rate": 1}},
              "150", "camera.resolution"),
             ("min-max pyramid", {**copy(big), "methods": ["maxmip"], "truth": {"rate": 1}},
              "120", "camera.resolution"),
             ("16384^2 procedural map", {**copy(big), "heightmap": {
                 "procedural": "sine", "size": [16384, 16384]}}, "256", "heightmap.size")]
    for name, scene, limit, field in cases:
        path = write(d, "big.json", json.dumps(scene))
        out = os.path.join(d, "out")
        r = run(["render", path, "--out", out, "--memory-limit", limit])
        expect_error(name, r, 2, [field, "needs about", f"limit of {limit} MB"], out)
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    check("no child grew past 400 MB", peak_mb < 400, f"{peak_mb:.0f} MB")


def shipped_paths(d):
    """"pgt:NAME" stays inside the shaders shipped with pgt: a name with "..", an absolute or
    an empty one is refused (exit 2 naming glsl), and no other file's text reaches the
    message."""
    for name in ["pgt:../../../../../../etc/passwd", "pgt:presets/../../../../../../etc/passwd",
                 "pgt:/etc/passwd", "pgt:", "pgt:./parallax.glsl"]:
        scene = copy(GOOD)
        scene["methods"] = [{"name": "m", "glsl": name, "function": "F"}]
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        r = run(["render", path, "--out", out])
        expect_error(name, r, 2, ["methods[0].glsl", "shipped with pgt"], out)
        check(f"{name}: no foreign text", "root:" not in r.stderr, r.stderr)
    scene = copy(GOOD)  # a real one still works
    scene["methods"] = [{"name": "m", "glsl": "pgt:parallax.glsl", "function": "ParallaxMapping",
                         "sampler": "heightMap"}]
    path = write(d, "scene.json", json.dumps(scene))
    r = run(["render", path, "--out", os.path.join(d, "ok")])
    check("pgt:parallax.glsl renders", r.returncode == 0, r.stderr)


def image_header_first(d):
    """A huge image is refused from its header, before decoding; a broken one in one line;
    a device or directory is refused, not read (no hang on /dev/zero)."""
    write(d, "huge.png", png(16384, 16384))  # the header alone: decoding would fail
    scene = copy(GOOD)
    scene["heightmap"] = {"file": "huge.png"}
    scene["truth"] = {"rate": 4}
    path = write(d, "scene.json", json.dumps(scene))
    out = os.path.join(d, "out")
    # The file holds no pixel data: a decode before the check would fail differently.
    expect_error("16384^2 header refused", run(["render", path, "--out", out]), 2,
                 ["truth.rate", "2^31"], out)
    write(d, "cut.png", png(8, 8, [[k * 8 + j for j in range(8)] for k in range(8)], truncate=60))
    scene["heightmap"] = {"file": "cut.png"}
    scene["truth"] = {"rate": 1}
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("truncated PNG: one line", run(["render", path, "--out", out]), 2,
                 ["heightmap.file", "cut.png"], out)
    for special in ["/dev/zero", d]:
        scene["heightmap"] = {"file": special}
        path = write(d, "scene.json", json.dumps(scene))
        expect_error(f"map {special}", run(["render", path, "--out", out], timeout=20), 2,
                     ["heightmap.file", "not a regular file"], out)
    scene = copy(GOOD)
    scene["base"] = {"type": "mesh", "file": "/dev/zero"}
    path = write(d, "scene.json", json.dumps(scene))
    expect_error("OBJ /dev/zero", run(["render", path, "--out", out], timeout=20), 2,
                 ["base.file", "not a regular file"], out)
    expect_error("scene /dev/zero", run(["render", "/dev/zero", "--out", out], timeout=20), 2,
                 ["/dev/zero", "not a regular file"], out)


def messages(d):
    """Bad values are bad input (exit 2) with one short, printable line naming the field."""
    text = json.dumps(GOOD)
    cases = {
        "1e400": (text.replace('"theta": 30', '"theta": 1e400'), ["camera.theta", "1e400"]),
        "duplicate key": (text.replace('"theta": 30', '"theta": 30, "theta": 40'),
                          ["camera.theta", "twice"]),
        "NUL in key": (text[:-1] + ', "a\\u0000b": 1}', ["a\\u0000b", "unknown key"]),
        "1 MB key": (text[:-1] + ', "' + "k" * 1000000 + '": 1}', ["unknown key"]),
    }
    for name, (scene, words) in cases.items():
        path = write(d, "scene.json", scene)
        out = os.path.join(d, "out")
        r = run(["render", path, "--out", out])
        expect_error(name, r, 2, ["scene.json"] + words, out)
        check(f"{name}: short", len(r.stderr) < 1000, f"{len(r.stderr)} characters")
    path = write(d, "scene.json", text)
    for args in [["render"], ["render", path], ["render", path, "--out", "x", "--bogus"],
                 ["render", path, "--out", "x", "--timing-repeats", "0"], ["frobnicate"], []]:
        r = run(args)
        expect_error(f"command line {args[:1]}", r, 2, ["pgt: error: command line"])
    r = run(["--help"])
    check("--help exits 0", r.returncode == 0 and "render" in r.stdout, r.stderr)


def messages4(d):
    """The fourth round's messages: an unknown --channels item is quoted, escaped and short;
    a body's shape errors name "body:N" (never pgt's wrapper), a comment-only body has no
    return; a sampler_state that is a keyword or the texture's own name names sampler_state;
    a NUL byte in a shader is named as such."""
    path = write(d, "scene.json", json.dumps(GOOD))
    out = os.path.join(d, "out")
    for item, words in (("uv\nx", ["--channels", "\\n"]), ("x" * 100000, ["--channels", "..."])):
        r = run(["render", path, "--out", out, "--channels", item])
        expect_error(f"--channels {item[:8]!r}", r, 2, words, out)
        check(f"--channels {item[:8]!r}: short", len(r.stderr) < 500, f"{len(r.stderr)} bytes")
    write(d, "f.glsl", "vec2 k(vec2 uv) { return uv; }\n")
    bodies = {"an unbalanced {": ("vec2 r = uv;\nif (s > 0.0) {\nreturn r;", "body:2"),
              "an unterminated comment": ("vec2 r = uv; /* left\nreturn r;", "body:1"),
              "a commented return": ("vec2 r = uv;\n// return r;", "no return"),
              "a comment-only body": ("// nothing here", "no return"),
              "a second main()": ("return uv;\n}\nvoid main() {", "body:")}
    for name, (body, word) in bodies.items():
        scene = copy(GOOD)
        scene["methods"] = [{"name": "b", "glsl": "f.glsl", "body": body, "sampler": ""}]
        r = run(["render", write(d, "body.json", json.dumps(scene)), "--out", out])
        expect_error(name, r, 2, ["body", word], out)
        check(f"{name}: not the wrapper", "wrapper" not in r.stderr, r.stderr)
    write(d, "h.hlsl", "Texture2D HeightTex; SamplerState samp;\n"
          "float2 F(float2 uv) { return uv + HeightTex.Sample(samp, uv).r * 0.0; }\n")
    for state in ("float", "HeightTex"):
        scene = copy(GOOD)
        scene["methods"] = [{"name": "h", "hlsl": "h.hlsl", "call": "F(uv)",
                             "sampler": "HeightTex", "sampler_state": state}]
        r = run(["render", write(d, "state.json", json.dumps(scene)), "--out", out])
        expect_error(f"sampler_state {state}", r, 2, ["sampler_state", state], out)
    write(d, "nul.glsl", "vec2 ParallaxMapping(vec2 uv, vec3 V) {\n\0 return uv; }\n")
    scene = copy(GOOD)
    scene["methods"] = [{"name": "n", "glsl": "nul.glsl", "sampler": ""}]
    r = run(["render", write(d, "nul.json", json.dumps(scene)), "--out", out])
    expect_error("a NUL byte", r, 2, ["nul.glsl", "NUL byte on line 2"], out)


def zero_pixel_uncertainty(d):
    """A frame where no pixel is compared reports nothing measured (null), not a perfect 0."""
    scene = copy(GOOD)
    scene["camera"] = {"type": "pinhole", "eye": [0, 0, 5], "target": [0, 5, 10],
                       "resolution": [8, 8]}  # looking up, away from the plane
    scene["truth"] = {"rate": 1, "uncertainty": True}
    path = write(d, "scene.json", json.dumps(scene))
    out = os.path.join(d, "out")
    r = run(["render", path, "--out", out])
    check("renders", r.returncode == 0, r.stderr)
    if r.returncode == 0:
        s = json.load(open(os.path.join(out, "summary.json")))
        u = s["truth"]["uncertainty"]
        check("uncertainty null", u["pixels_compared"] == 0 and u["p50_texels"] is None and
              u["p99_texels"] is None and u["max_texels"] is None, json.dumps(u))
        check("method null", s["methods"][0]["error_texels"]["mean"] is None,
              json.dumps(s["methods"][0]["error_texels"]))


def stale_temporaries(d):
    """A killed writer's temporaries are removed by the next run into the directory; a live
    one's are kept."""
    path = write(d, "scene.json", json.dumps(GOOD))
    out = os.path.join(d, "out")
    os.makedirs(out)
    dead = subprocess.Popen(["true"])
    dead.wait()
    stale = [f".frame.exr.pgt-tmp.{dead.pid}.abc", "frame.tmp1a2b3c.exr"]
    live = f".frame.exr.pgt-tmp.{os.getpid()}.abc"
    for name in stale + [live]:
        write(out, name, "partial")
    r = run(["render", path, "--out", out])
    left = os.listdir(out)
    check("renders", r.returncode == 0, r.stderr)
    check("stale removed", not any(n in left for n in stale), f"{left}")
    check("live kept", live in left, f"{left}")


def no_litter(d):
    """A failed render or fit removes the --out directory it created, and only that: every
    GLSL compile, sampler and uniform error comes after --out is made; a directory that was
    there before stays, with what was in it. A sweep compiles its shaders before it makes
    its DIR."""
    bad = write(d, "bad.glsl", "vec2 F(vec2 uv, vec3 V) { return uv +; }\n")
    good = write(d, "good.glsl", "uniform sampler2D h;\nuniform float k;\n"
                 "vec2 F(vec2 uv, vec3 V) { return uv + k * texture(h, uv).r * V.xy; }\n")
    methods = {
        "compile error": {"name": "m", "glsl": bad, "function": "F"},
        "missing sampler": {"name": "m", "glsl": good, "function": "F", "sampler": "nope"},
        "missing uniform": {"name": "m", "glsl": good, "function": "F", "sampler": "h",
                            "uniforms": {"nope": 1.0}},
    }
    for name, method in methods.items():
        scene = copy(GOOD)
        scene["methods"] = ["parallax", method]
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "new", "deeper", "out")
        r = run(["render", path, "--out", out])
        check(f"{name}: exit 2", r.returncode == 2, r.stderr)
        check(f"{name}: created parents removed too", not os.path.exists(os.path.join(d, "new")),
              str(os.listdir(d)))
        if name == "compile error":  # a study's shaders compile before DIR is made
            scene["sweep"] = {"theta": [0, 40], "resolution": [16, 16]}
            spath = write(d, "study.json", json.dumps(scene))
            r = run(["sweep", spath, "--out", out])
            check("sweep with a compile error: exit 2, no DIR",
                  r.returncode == 2 and not os.path.exists(os.path.join(d, "new")), r.stderr)
        kept = os.path.join(d, "kept")
        os.makedirs(kept, exist_ok=True)
        write(kept, "mine.txt", "x")
        r = run(["render", path, "--out", kept])
        check(f"{name}: a directory that existed stays", r.returncode == 2 and
              sorted(os.listdir(kept)) == ["mine.txt"], f"{os.listdir(kept)}")
    # fit: scenes it refuses after --out was made (only presets: nothing to fit; a view at
    # theta 90 sees no pixel): exit 2 naming the field, no --out, no fit.json.
    for name, edit, field in [
            ("only presets", lambda s: s.update(methods=[{"preset": "godot"}]), "methods"),
            ("theta 90", lambda s: s.update(fit={"theta": [30, 90], "resolution": [8, 8],
                                                 "steps": [8], "refine": 0}), "fit.theta = 90")]:
        scene = copy(GOOD)
        edit(scene)
        path = write(d, "fit.json", json.dumps(scene))
        out = os.path.join(d, "fit_out")
        expect_error(f"fit {name}", run(["fit", path, "--out", out]), 2, ["fit.json", field], out)


def stress_folders(d):
    """pgt stress on folders it cannot read (a symlink loop as the folder, a loop among its
    scenes): exit 2 naming the path, never an internal error, no --out left."""
    os.symlink("l2", os.path.join(d, "l1"))
    os.symlink("l1", os.path.join(d, "l2"))
    folder = os.path.join(d, "scenes")
    os.makedirs(folder)
    os.symlink("loop.json", os.path.join(folder, "loop.json"))
    write(folder, "good.json", json.dumps(GOOD))
    for name, path, words in [("loop as the folder", os.path.join(d, "l1"), ["l1", "cannot read"]),
                              ("loop among the scenes", folder, ["loop.json"])]:
        out = os.path.join(d, "out")
        expect_error(name, run(["stress", path, "--out", out]), 2, words, out)


def long_precompute(d):
    """A relaxed cone map build (minutes at 2048^2) says how far it is and how long it has left
    after 3 s on stderr, and SIGINT stops it within a second, leaving nothing."""
    scene = copy(GOOD)
    scene["heightmap"] = {"procedural": "bricks", "size": [768, 768]}
    scene["methods"] = ["relaxed_cone"]
    path = write(d, "cone.json", json.dumps(scene))
    out = os.path.join(d, "out")
    p = subprocess.Popen([PGT, "render", path, "--out", out], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    # The first relaxed-cone progress line, after its quiet 3 s (a slow build, as under the
    # sanitizers, first reports the cone map it starts from).
    line = p.stderr.readline()
    while line and "relaxed cone map" not in line:
        line = p.stderr.readline()
    running = p.poll() is None
    t0 = time.time()
    p.send_signal(signal.SIGINT)
    p.wait(timeout=30)
    check("progress with time left", "relaxed cone map 768x768:" in line and "left" in line, line)
    check("still building when it spoke", running)
    check("stops within a second", time.time() - t0 < 1.0, f"{time.time() - t0:.2f} s")
    check("nothing left", not os.path.exists(out))


def signals(d):
    """SIGINT or SIGTERM stops the CLI at once and leaves nothing it made: no temporaries, no
    --out a render created; a sweep keeps its finished rows."""
    scene = copy(GOOD)
    scene["heightmap"] = {"procedural": "bricks", "size": [256, 256]}
    scene["camera"]["resolution"] = [1536, 1536]
    scene["methods"] = ["parallax", {"name": "pom", "min_layers": 64, "max_layers": 128}]
    scene["truth"] = {"rate": 4}
    path = write(d, "slow.json", json.dumps(scene))
    for sig in (signal.SIGINT, signal.SIGTERM):
        out = os.path.join(d, f"render_{sig}")
        p = subprocess.Popen([PGT, "render", path, "--out", out], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        deadline = time.time() + 60  # until the frame's files are being written
        while time.time() < deadline and p.poll() is None and not (
                os.path.isdir(out) and any("frame.exr" in n for n in os.listdir(out))):
            time.sleep(0.01)
        time.sleep(0.3)
        running = p.poll() is None
        t0 = time.time()
        p.send_signal(sig)
        p.wait(timeout=30)
        check(f"{sig.name}: killed mid-render", running, "finished before the signal")
        check(f"{sig.name}: stops within a second", time.time() - t0 < 1.0,
              f"{time.time() - t0:.2f} s")
        check(f"{sig.name}: exit by the signal", p.returncode == -sig, f"exit {p.returncode}")
        check(f"{sig.name}: nothing left", not os.path.exists(out),
              f"{os.listdir(out) if os.path.exists(out) else ''}")
    study = copy(SWEEP)
    study["camera"]["resolution"] = [128, 128]
    study["heightmap"]["size"] = [64, 64]
    study["sweep"]["theta"] = list(range(0, 90, 2))
    path = write(d, "study.json", json.dumps(study))
    out = os.path.join(d, "study")
    p = subprocess.Popen([PGT, "sweep", path, "--out", out, "--no-report"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    csv_path = os.path.join(out, "results.csv")
    deadline = time.time() + 60
    while time.time() < deadline and p.poll() is None and not (
            os.path.exists(csv_path) and sum(1 for _ in open(csv_path)) > 5):
        time.sleep(0.01)
    p.send_signal(signal.SIGINT)
    p.wait(timeout=30)
    left = os.listdir(out)
    check("sweep: rows kept", sum(1 for _ in open(csv_path)) > 5)
    check("sweep: no temporaries", not any(".pgt-tmp." in n for n in left), f"{left}")
    r = sweep(path, out)
    check("sweep: resumes", r.returncode == 0 and "resumed" in r.stdout, r.stderr)


if __name__ == "__main__":
    main([deep_json, obj_indices, shell_injection, gl_texture_limit, concurrent_sweeps,
          study_identity, results_csv_state, labels, full_disk, render_checks_out_first,
          memory_estimates, image_header_first, messages, zero_pixel_uncertainty,
          stale_temporaries, no_litter, signals, memory_beyond_the_frame, shipped_paths,
          stress_folders, long_precompute, outputs_whole, messages4])
