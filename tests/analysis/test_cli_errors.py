#!/usr/bin/python3
"""ctest: bad input through the real CLI. Each case must exit with the documented status
(2 bad input, 3 unwritable output), print exactly one error line naming the file and the
field, and leave no output directory behind. Arguments: PGT_BINARY SOURCE_DIR."""
import json
import os
import subprocess
import sys
import tempfile

pgt = sys.argv[1]
good = {"heightmap": {"procedural": "sine", "size": [8, 8]}, "base": {"type": "plane"},
        "camera": {"type": "orthographic", "theta": 30, "resolution": [8, 8]},
        "methods": ["parallax"], "truth": {"rate": 1}}


def variant(path, value):
    s = json.loads(json.dumps(good))
    node = s
    for k in path[:-1]:
        node = node[k]
    if value is None:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return s


cases = [  # (name, scene or raw text, expected status, words the message must contain)
    ("malformed JSON", '{"heightmap": {"procedural": "sine"},\n "base": ,}', 2, ["line 2"]),
    ("misspelt key", variant(["camera", "thetta"], 10), 2, ["camera.thetta", "did you mean"]),
    ("wrong type", variant(["camera", "theta"], "steep"), 2, ["camera.theta", "number"]),
    ("resolution 0", variant(["camera", "resolution"], [0, 8]), 2, ["camera.resolution"]),
    ("resolution absurd", variant(["camera", "resolution"], [100000, 8]), 2, ["camera.resolution"]),
    ("theta 95", variant(["camera", "theta"], 95), 2, ["camera.theta", "95"]),
    ("rate 0", variant(["truth", "rate"], 0), 2, ["truth.rate"]),
    ("missing image", variant(["heightmap"], {"file": "nope.png"}), 2, ["heightmap.file", "nope.png"]),
    ("empty methods", variant(["methods"], []), 2, ["methods", "empty"]),
    ("unknown method", variant(["methods"], ["parralax"]), 2, ["methods[0].name", "tangent_plane"]),
    ("missing shader", variant(["methods"], [{"name": "mine", "glsl": "nope.glsl"}]), 2,
     ["methods[0].glsl", "nope.glsl"]),
    ("unknown preset", variant(["methods"], [{"preset": "unreal"}]), 2,
     ["methods[0].preset", "godot_deep"]),
]
failures = []
with tempfile.TemporaryDirectory() as d:
    for name, scene, want, words in cases:
        path = os.path.join(d, "scene.json")
        with open(path, "w") as f:
            f.write(scene if isinstance(scene, str) else json.dumps(scene))
        out = os.path.join(d, "out_" + name.replace(" ", "_"))
        r = subprocess.run([pgt, "render", path, "--out", out], capture_output=True, text=True)
        lines = [l for l in r.stderr.splitlines() if l.strip()]
        ok = (r.returncode == want and len(lines) == 1 and "scene.json" in lines[0]
              and all(w in lines[0] for w in words) and not os.path.exists(out))
        if not ok:
            failures.append(f"{name}: exit {r.returncode} (want {want}), stderr {r.stderr!r}")
    # An output path that cannot be written: status 3.
    path = os.path.join(d, "scene.json")
    json.dump(good, open(path, "w"))
    blocker = os.path.join(d, "file")
    open(blocker, "w").write("x")
    r = subprocess.run([pgt, "render", path, "--out", os.path.join(blocker, "sub")],
                       capture_output=True, text=True)
    if r.returncode != 3 or "cannot" not in r.stderr:
        failures.append(f"unwritable output: exit {r.returncode}, stderr {r.stderr!r}")
    # A malformed GL device: status 2 naming the option (checked before any work).
    r = subprocess.run([pgt, "render", path, "--out", os.path.join(d, "gl"), "--gl-device",
                        "gpu0"], capture_output=True, text=True)
    if r.returncode != 2 or "--gl-device" not in r.stderr or os.path.exists(os.path.join(d, "gl")):
        failures.append(f"bad --gl-device: exit {r.returncode}, stderr {r.stderr!r}")
    # An Embree kernel that does not exist: status 2 naming the variable, before any output.
    r = subprocess.run([pgt, "render", path, "--out", os.path.join(d, "isa")],
                       capture_output=True, text=True, env={**os.environ, "PGT_EMBREE_ISA": "avx9"})
    if (r.returncode != 2 or "PGT_EMBREE_ISA" not in r.stderr or "avx9" not in r.stderr
            or os.path.exists(os.path.join(d, "isa"))):
        failures.append(f"bad PGT_EMBREE_ISA: exit {r.returncode}, stderr {r.stderr!r}")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"{len(cases) + 3} passed, 0 failed")
