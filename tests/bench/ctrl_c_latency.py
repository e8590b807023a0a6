#!/usr/bin/python3
"""Benchmark (not a test): how long Ctrl-C takes to stop pgt.render in Python, from SIGINT to
KeyboardInterrupt, in the stages a render spends its time in: a C++ method over a large
frame, a slow GLSL shader's draw, a shader's compile (a child process), and a 16384^2 map's
generation and truth (a gigabyte of heights; SIGINT at a seeded moment of its 40 s). The tests assert
only that the interrupt happens and leaves nothing (python.module, hostile.python_cancel);
the latency depends on the machine's load, so it is measured here.
Usage: /usr/bin/python3 tests/bench/ctrl_c_latency.py BUILD_DIR [TRIALS]   (default 5)"""
import json
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import time

BUILD = os.path.abspath(sys.argv[1])
TRIALS = int(sys.argv[2]) if len(sys.argv) > 2 else 5
CHILD = r"""
import sys, time
import pgt
print("started", flush=True)
try:
    pgt.render(sys.argv[1], out=sys.argv[2])
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""
BASE = {"heightmap": {"procedural": "bricks", "size": [256, 256]},
        "base": {"type": "plane", "infinite": True},
        "camera": {"type": "orthographic", "theta": 60, "frame": "fill"}, "truth": {"rate": 2}}


def scenes(d):
    """(name, scene path) of each stage."""
    out = []
    cpp = dict(BASE, methods=[{"name": "pom", "min_layers": 64, "max_layers": 128}])
    cpp["camera"] = dict(BASE["camera"], resolution=[1536, 1536])
    out.append(("C++ frame", cpp))
    with open(os.path.join(d, "slow.glsl"), "w") as f:
        f.write("uniform sampler2D depthMap;\nvec2 ParallaxMapping(vec2 uv, vec3 V) {\n"
                "  float x = texture(depthMap, uv).r;\n"
                "  for (int i = 0; i < 20000; ++i) x = sin(x + uv.x);\n"
                "  return uv + V.xy * x * 1e-9; }\n")
    draw = dict(BASE, methods=[{"name": "slow", "glsl": "slow.glsl"}])
    draw["camera"] = dict(BASE["camera"], resolution=[512, 512])
    out.append(("GLSL draw", draw))
    with open(os.path.join(d, "many.glsl"), "w") as f:
        f.write("\n".join(f"float g{i}(float a) {{ return a; }}" for i in range(250000)) +
                "\nvec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n")
    compile_ = dict(BASE, methods=[{"name": "many", "glsl": "many.glsl"}])
    compile_["camera"] = dict(BASE["camera"], resolution=[64, 64])
    out.append(("shader compile", compile_))
    huge = {"heightmap": {"procedural": "bricks", "size": [16384, 16384]},
            "base": {"type": "plane"}, "methods": ["parallax"],
            "camera": {"type": "orthographic", "theta": 30, "resolution": [64, 64]},
            "truth": {"rate": 1, "uncertainty": False}}
    out.append(("16384^2 map", huge))
    paths = []
    for name, scene in out:
        path = os.path.join(d, name.replace(" ", "_") + ".json")
        json.dump(scene, open(path, "w"))
        paths.append((name, path))
    return paths


def main():
    rng = random.Random(1)
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"))
    with tempfile.TemporaryDirectory() as d:
        for name, path in scenes(d):
            lat = []
            for trial in range(TRIALS):
                out = os.path.join(d, f"out{trial}")
                p = subprocess.Popen(["/usr/bin/python3", "-c", CHILD, path, out],
                                     stdout=subprocess.PIPE, text=True, env=env)
                p.stdout.readline()
                # A seeded moment inside the stage (the huge map's anywhere in its run).
                time.sleep(rng.uniform(0.2, 35.0) if name.startswith("16384") else
                           1.0 + rng.random())
                sent = time.time()
                p.send_signal(signal.SIGINT)
                line = p.stdout.readline().strip()
                p.wait()
                if line == "interrupted":
                    lat.append(time.time() - sent)
            if lat:
                print(f"{name}: {len(lat)} of {TRIALS} interrupted; SIGINT to KeyboardInterrupt "
                      f"median {statistics.median(lat):.2f} s, max {max(lat):.2f} s")
            else:
                print(f"{name}: never interrupted (finished first?)")


main()
