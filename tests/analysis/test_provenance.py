#!/usr/bin/python3
"""ctest: every output says what made it (docs/outputs.md "Provenance"): `pgt --version`;
summary.json's provenance block and frame.exr's pgt:* header attributes (the same commit and
scene hash); a study's provenance.json, one entry per run (a resume adds one, --fresh starts
again), stated in report.md's header; fit.json; the GL's renderer when a GLSL method ran; the
Embree kernel PGT_EMBREE_ISA forces; whether large buffers were on huge pages; `pgt methods` lists what pgt can measure. Arguments: PGT_BINARY SOURCE_DIR."""
import json
import os
import re
import subprocess
import sys
import tempfile

PGT, SRC = sys.argv[1], sys.argv[2]
failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)[-1500:]))
    if not ok:
        failures.append(name)


def run(*args, env=None):
    return subprocess.run([PGT, *args], capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, **(env or {})))


def complete(p):
    return (re.fullmatch(r"\d+\.\d+\.\d+", p["pgt"]["version"]) and p["pgt"]["commit"]
            and p["pgt"]["build_type"] and p["pgt"]["compiler"] and p["machine"]["cpu"]
            and p["machine"]["embree_kernel"] and p["machine"]["os"]
            and re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", p["date"])
            and set(p["libraries"]) == {"embree", "opensubdiv", "openimageio", "openexr",
                                        "onetbb"})


r = run("methods")
presets = r.stdout.split("presets:")[-1].splitlines()[1:]
builtins = r.stdout.split("presets:")[0]
check("pgt methods: every built-in and each preset with its summary and source keys",
      r.returncode == 0 and re.search(r"\n  pom +steep's march.*"
                                      r"\[brawley2004 tatarchuk2006 devries2020\]\n"
                                      r" +min_layers 1-4096", builtins) is not None
      and "  relaxed_cone" in builtins and "[premecz2006 szirmaykalos2008]" in builtins
      and len(presets) >= 29
      and all(re.search(r"\[[a-z0-9 ]+\]$", l) for l in presets)
      and any(l.split()[0] == "godot" and "Godot 4" in l and l.endswith("[godot4]")
              for l in presets), r.stdout)

r = run("--version")
check("--version: exit 0, version, commit and Embree", r.returncode == 0 and
      re.match(r"pgt \d+\.\d+\.\d+ \(commit ", r.stdout) and "embree 3." in r.stdout, r)

with tempfile.TemporaryDirectory() as d:
    scene = json.load(open(os.path.join(SRC, "scenes", "default.json")))
    scene["camera"]["resolution"] = [24, 24]
    scene["methods"] = ["parallax", {"preset": "godot"}]
    scene["sweep"] = {"theta": [0, 60], "scale": [0.05], "bias_ratio": [-0.5],
                      "timing": {"repeats": 0}}
    scene.pop("fit", None)
    path = os.path.join(d, "scene.json")
    json.dump(scene, open(path, "w"))
    out = os.path.join(d, "render")
    r = run("render", path, "--out", out, "--no-timing", env={"PGT_EMBREE_ISA": "sse2"})
    check("render", r.returncode == 0, r.stderr)
    prov = json.load(open(os.path.join(out, "summary.json")))["provenance"]
    check("summary.json: a whole provenance block", complete(prov), prov)
    check("the command as given", prov["command"].endswith(f"render {path} --out {out} --no-timing"),
          prov["command"])
    check("the kernel PGT_EMBREE_ISA forced", prov["machine"]["embree_kernel"] ==
          "sse2 (PGT_EMBREE_ISA)", prov["machine"])
    check("the GL that ran the GLSL preset", "renderer" in prov.get("gl", {}), prov)
    # The command asks glibc for huge pages when it starts, unless the environment names the
    # tunable (cli/main.cpp restartOnHugePages); glibc.malloc.hugetlb=0 keeps 4 KB pages.
    asked = "glibc.malloc.hugetlb" not in os.environ.get("GLIBC_TUNABLES", "")
    check("huge pages, as the command asks when it starts",
          prov["machine"]["huge_pages"] is asked, prov["machine"])
    kept = os.path.join(d, "render_4k")
    r = run("render", path, "--out", kept, "--no-timing",
            env={"GLIBC_TUNABLES": "glibc.malloc.hugetlb=0"})
    check("glibc.malloc.hugetlb=0: 4 KB pages", r.returncode == 0 and
          json.load(open(os.path.join(kept, "summary.json")))["provenance"]["machine"]
          ["huge_pages"] is False, r.stderr)
    check("a 40-digit scene hash", re.fullmatch(r"[0-9A-F]{40}", prov["scene_sha1"]), prov)
    try:
        import OpenImageIO as oiio
        spec = oiio.ImageInput.open(os.path.join(out, "frame.exr")).spec()
        check("frame.exr: the same commit and scene hash",
              spec.getattribute("pgt:commit") == prov["pgt"]["commit"] and
              spec.getattribute("pgt:scene_sha1") == prov["scene_sha1"] and
              json.loads(spec.getattribute("pgt:provenance"))["pgt"] == prov["pgt"],
              [spec.getattribute("pgt:commit"), spec.getattribute("pgt:scene_sha1")])
    except ImportError:
        print("skip frame.exr's header: no python3-openimageio")

    study = os.path.join(d, "study")
    r = run("sweep", path, "--out", study, "--max-cases", "1", "--no-report")
    r = run("sweep", path, "--out", study)
    runs = json.load(open(os.path.join(study, "provenance.json")))["runs"]
    check("a resumed study: two runs, each with its cases", len(runs) == 2 and
          [x["cases_run"] for x in runs] == [1, 1] and all(complete(x) for x in runs), runs)
    report = os.path.join(study, "report.md")
    if os.path.exists(report):
        text = open(report).read()
        check("report.md states the runs", "Made by 2 run(s)" in text and
              runs[-1]["pgt"]["commit"] in text and
              (", huge pages" if runs[-1]["machine"]["huge_pages"] else ", 4 KB pages") in text,
              text[:1500])
    r = run("sweep", path, "--out", study, "--fresh", "--no-report")
    runs = json.load(open(os.path.join(study, "provenance.json")))["runs"]
    check("--fresh starts the runs again", len(runs) == 1 and runs[0]["cases_run"] == 2, runs)

    scene["fit"] = {"theta": [30], "steps": [8], "scale_factors": [1], "bias_ratios": [-0.5],
                    "refine": 0, "resolution": [16, 16], "methods": ["pom"]}
    json.dump(scene, open(path, "w"))
    r = run("fit", path, "--out", os.path.join(d, "fit"))
    fit = json.load(open(os.path.join(d, "fit", "fit.json"))) if r.returncode == 0 else {}
    check("fit.json: provenance", complete(fit.get("provenance", {})), r.stderr)

if failures:
    print(f"{len(failures)} failed: {', '.join(failures)}")
    sys.exit(1)
print("all passed")
