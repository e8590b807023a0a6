#!/usr/bin/python3
"""ctest: what pgt starts beside itself (docs/testing.md "What pgt promises"): shader compilers
given hostile input are bounded before the GL's compiler sees it (a crash or a hang there is
pgt's), and no child -- a compiler's, the report's -- outlives pgt, however pgt ends.
Arguments: PGT_BINARY SOURCE_DIR CLASS."""
import json
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_common import *  # noqa: E402,F401,F403  (the harness: run, check, scenes, ...)


def shader_scene(d, name, source, kind="glsl", **entry):
    """A GLSL (or HLSL) method whose file is `source`, in a tiny frame."""
    write(d, f"{name}.{kind}", source)
    scene = copy(GOOD)
    scene["methods"] = [dict({"name": "mine", kind: f"{name}.{kind}"}, **entry)]
    return write(d, f"{name}.json", json.dumps(scene))


def chain(n):
    """n functions, each calling the last: Mesa inlines them into a tree n deep."""
    fns = ["float f0(float a) { return a; }"]
    fns += [f"float f{i}(float a) {{ return f{i - 1}(a) + 1.0; }}" for i in range(1, n)]
    return "\n".join(fns) + (f"\nvec2 ParallaxMapping(vec2 uv, vec3 V) {{ "
                             f"return uv + vec2(f{n - 1}(0.0) * 0.0); }}\n")


def shader_bounds(d):
    """The tester's shaders that crashed the GL's compiler (exit 139) or ran without end: each is
    refused with exit 2 and one line naming the file and the bound it passed."""
    sum_terms = " + ".join(["uv.x"] * 20000)
    macro = "\n".join(["#define M0 uv.x"] + [f"#define M{i} (M{i - 1} + M{i - 1})"
                                             for i in range(1, 23)])
    cases = [
        ("a 20,000-term sum", shader_scene(d, "sum", "vec2 ParallaxMapping(vec2 uv, vec3 V) { "
                                           f"float x = {sum_terms}; return uv + vec2(x * 0.0); }}\n"),
         [], ["sum.glsl", "nested more than 2000 levels"]),
        ("a chain of 20,000 calls", shader_scene(d, "chain", chain(20000)), [],
         ["chain.glsl", "functions defined (the bound is 4096)"]),
        ("a chain of 1,000 calls", shader_scene(d, "chain1k", chain(1000)), [],
         ["chain1k.glsl", "1002 functions in a chain of calls (the bound is 64)"]),
        ("a call of 20,000 terms", shader_scene(
            d, "call", "vec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n",
            call="uv + vec2(0.0 * (" + "+".join(["s"] * 20000) + "))"),
         [], ["call.glsl", "nested more than 2000 levels"]),
        ("a 1 MB call", shader_scene(
            d, "bigcall", "vec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n",
            call="uv + vec2(0.0 * (" + "+".join(["V.x"] * 250000) + "))"),
         [], ["bigcall.json", "call", "at most 65536"]),
        ("a 22-level macro bomb", shader_scene(
            d, "macro", macro + "\nvec2 ParallaxMapping(vec2 uv, vec3 V) { float x = M22; "
            "return uv + vec2(x * 0.0); }\n"),
         ["--memory-limit", "400"], ["macro.glsl", "memory limit"]),
        ("250,000 functions", shader_scene(
            d, "many", "\n".join(f"float g{i}(float a) {{ return a; }}" for i in range(250000)) +
            "\nvec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n"),
         ["--memory-limit", "400"], ["many.glsl"]),
    ]
    for name, path, extra, words in cases:
        out = os.path.join(d, "out_" + os.path.basename(path))
        r = run(["render", path, "--out", out] + extra, timeout=200)
        expect_error(name, r, 2, words, out)
    # An HLSL file that includes itself: refused at the include depth, for render and fit.
    path = shader_scene(d, "selfinc", '#include "selfinc.hlsl"\n'
                        "float2 ParallaxMapping(float2 uv, float3 V) { return uv; }\n", "hlsl",
                        call="ParallaxMapping(uv, V) + V.xy * s")
    for command in ("render", "fit"):
        out = os.path.join(d, "out_selfinc_" + command)
        r = run([command, path, "--out", out], timeout=200)
        check(f"self-include: {command} refused", r.returncode == 2 and
              "includes nest more than 32" in r.stderr and "selfinc.hlsl" in r.stderr,
              f"exit {r.returncode}, {r.stderr[:400]!r}")
        check(f"self-include: {command} leaves no out", not os.path.exists(out))
    # Within the bounds: a chain of 40 calls and a 1,000-term sum compile and run.
    ok = shader_scene(d, "fine", chain(40).replace("return uv +", "return uv + vec2(" + " + ".join(
        ["uv.x"] * 1000) + ") * 0.0 +"), sampler="")
    r = run(["render", ok, "--out", os.path.join(d, "fine_out")], timeout=200)
    check("within the bounds: renders", "refused before the GL" not in r.stderr,
          f"exit {r.returncode}, {r.stderr[:400]!r}")
    # A define's value or a call holding a line break, a CR, a NUL or a backslash: one line
    # naming the field (it was a compiler's multi-line message naming neither).
    for what, text in (("CR", "1\r2"), ("LF", "1\n2"), ("NUL", "1\u00002"), ("backslash", "1 \\"),
                       ("escape", "1\u001b")):
        path = shader_scene(d, "def", "vec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n",
                            defines={"X": text})
        expect_error(f"defines holding a {what}", run(["render", path, "--out",
                                                       os.path.join(d, "o")]), 2,
                     ["def.json", "defines.X", "one line of shader text"], os.path.join(d, "o"))
        path = shader_scene(d, "callt", "vec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n",
                            call="uv + " + text)
        expect_error(f"a call holding a {what}", run(["render", path, "--out",
                                                      os.path.join(d, "o")]), 2,
                     ["callt.json", "call", "one line of shader text"], os.path.join(d, "o"))
    # An HLSL call that does not read V (its input optimised away) compiles: it failed with
    # "pgt_hlsl_v undeclared".
    for call in ("uv + 0.0 * s", "uv + 0.0 * V.xy"):
        path = shader_scene(d, "nov", "Texture2D depthMap; SamplerState samp;\n"
                            "float2 ParallaxMapping(float2 uv) { "
                            "return uv + depthMap.Sample(samp, uv).r * 1e-9; }\n", "hlsl",
                            call=call.replace("uv +", "ParallaxMapping(uv) +"))
        r = run(["render", path, "--out", os.path.join(d, "nov_out")], timeout=200)
        check(f"HLSL call {call!r} without V compiles", r.returncode == 0,
              f"exit {r.returncode}, {r.stderr[:400]!r}")


def shader_text(d):
    """What pgt reads in a shader file before a compiler does (its samplers, functions, enums,
    includes, sampler defaults, #pragma once) on text no engine writes: a 300,000-character
    name, a 300,000-space run, 150,000 parameters, a 40,000-member enum, a 300,000-character
    include name, a body of 20,000 lines. Each is exit 2 with a message naming the file (a
    regular-expression scan of these crashed pgt, exit 139), within the compile time limit."""
    F = "float2 F(float2 uv, float3 V) { return uv; }\n"
    cases = [
        ("a 300,000-character name", shader_scene(
            d, "ident", "float f(" + "a" * 300000 + " = 1) { return 0; }\n" + F, "hlsl",
            function="F"), ["ident.hlsl"]),
        ("300,000 spaces", shader_scene(
            d, "space", "Texture2D" + " " * 300000 + "x;\n" + F, "hlsl", function="F"),
         ["space.hlsl"]),
        ("150,000 parameters and a sampler default", shader_scene(
            d, "params", "float f(" + "a, " * 150000 + "SamplerState s = t) { return 0; }\n" + F,
            "hlsl", function="F"), ["params.hlsl"]),
        ("a 40,000-member enum", shader_scene(
            d, "enum", "enum E { " + ", ".join(f"A{i}" for i in range(40000)) + " };\n" + F,
            "hlsl", function="F"), ["enum.hlsl"]),
        ("a 300,000-character include", shader_scene(
            d, "inc", '#include "' + "a" * 300000 + '"\nvec2 F(vec2 uv, vec3 V) { return uv; }\n',
            function="F"), ["inc.glsl", "#include"]),
    ]
    for name, path, words in cases:
        out = os.path.join(d, "out_" + os.path.basename(path))
        r = run(["render", path, "--out", out, "--no-timing"], timeout=200)
        first = (r.stderr.splitlines() or [""])[0]  # a compiler's messages follow the first line
        check(name, r.returncode == 2 and all(w in first for w in words) and
              not os.path.exists(out), f"exit {r.returncode} (want 2), {r.stderr[:400]!r}")
    # A body of 20,000 lines compiles through the same scans (and the GL's bounds).
    body = ["float x = 0.0;"] + ["x += uv.x * 0.0;"] * 20000 + ["return uv + vec2(x);"]
    path = shader_scene(d, "body", "float unused() { return 1.0; }\n", body=body, sampler="")
    r = run(["render", path, "--out", os.path.join(d, "body_out"), "--no-timing"], timeout=200)
    check("a 20,000-line body runs or is refused by a bound, never a crash",
          r.returncode in (0, 2), f"exit {r.returncode}, {r.stderr[:400]!r}")


def children_of(pid):
    """The pids whose parent is `pid` (from /proc)."""
    out = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = open(f"/proc/{entry}/stat").read()
        except OSError:
            continue
        if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
            out.append(int(entry))
    return out


def alive(pid):
    try:
        stat = open(f"/proc/{pid}/stat").read()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def kill_with_children(d, name, args, sig):
    """Starts pgt, waits for a child of it, sends `sig` to pgt alone, and checks that the child
    is gone soon after pgt (it had lived on for 9 to 30+ s)."""
    p = subprocess.Popen([PGT] + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    kids, deadline = [], time.time() + 120
    while time.time() < deadline and p.poll() is None and not kids:
        kids = children_of(p.pid)
        time.sleep(0.01)
    check(f"{name}: a child was started", bool(kids), f"exit {p.poll()}")
    os.kill(p.pid, sig)
    p.wait(timeout=60)
    deadline = time.time() + 5  # PR_SET_PDEATHSIG: at once; 5 s for a loaded machine
    while time.time() < deadline and any(alive(k) for k in kids):
        time.sleep(0.05)
    left = [k for k in kids if alive(k)]
    check(f"{name}: no child outlives pgt", not left, f"{left} still running")
    for k in left:
        os.kill(k, signal.SIGKILL)


def orphans(d):
    """SIGKILL, SIGTERM or SIGINT to pgt alone (not its group): its compile child (a slow
    parse) and its report child die with it."""
    slow = shader_scene(d, "slow", "\n".join(f"float g{i}(float a) {{ return a; }}"
                                             for i in range(250000)) +
                        "\nvec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n")
    for sig in (signal.SIGKILL, signal.SIGTERM, signal.SIGINT):
        kill_with_children(d, f"render's compiler, {sig.name}",
                           ["render", slow, "--out", os.path.join(d, f"slow_{sig}"),
                            "--memory-limit", "3000"], sig)
    study = copy(SWEEP)
    study["sweep"]["theta"] = [0, 30, 60]
    path = write(d, "study.json", json.dumps(study))
    for sig in (signal.SIGKILL, signal.SIGTERM):
        kill_with_children(d, f"sweep's report, {sig.name}",
                           ["sweep", path, "--out", os.path.join(d, f"study_{sig}"), "--fresh"],
                           sig)


PY_CHILD = r"""
import os, sys, time
import pgt
print("started", flush=True)
t0 = time.time()
try:
    pgt.render(sys.argv[1], out=sys.argv[2])
    print("finished", flush=True)
except KeyboardInterrupt:
    print(f"interrupted {time.time() - t0:.3f}", flush=True)
"""


def python_cancel(d):
    """Ctrl-C in Python during a shader's compile (its child) and during a slow shader's draw
    raises KeyboardInterrupt, leaves no child and no out. The latency is printed, not asserted
    (tests/bench/ctrl_c_latency.py measures it)."""
    module = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(PGT))), "python")
    if not os.path.isdir(os.path.join(module, "pgt")):
        print(f"python_cancel: no module in {module}: skipped")
        return
    slow_parse = shader_scene(d, "bomb", "\n".join(f"float g{i}(float a) {{ return a; }}"
                                                   for i in range(250000)) +
                              "\nvec2 ParallaxMapping(vec2 uv, vec3 V) { return uv; }\n")
    write(d, "slow.glsl", "uniform sampler2D depthMap;\n"
          "vec2 ParallaxMapping(vec2 uv, vec3 V) { float x = texture(depthMap, uv).r;\n"
          "  for (int i = 0; i < 20000; ++i) x = sin(x + uv.x);\n"
          "  return uv + V.xy * x * 1e-9; }\n")
    scene = copy(GOOD)
    scene["camera"]["resolution"] = [512, 512]
    scene["methods"] = [{"name": "slow", "glsl": "slow.glsl"}]
    slow_draw = write(d, "slow_draw.json", json.dumps(scene))
    env = dict(os.environ, PYTHONPATH=module)
    for name, path in (("compile", slow_parse), ("draw", slow_draw)):
        out = os.path.join(d, "py_out_" + name)
        p = subprocess.Popen(["/usr/bin/python3", "-c", PY_CHILD, path, out],
                             stdout=subprocess.PIPE, text=True, env=env)
        check(f"python {name}: started", p.stdout.readline().strip() == "started")
        time.sleep(2.0)  # inside the compile (its child parses for seconds) or the draw
        kids = children_of(p.pid)
        sent = time.time()
        p.send_signal(signal.SIGINT)
        line = p.stdout.readline().strip()
        p.wait(timeout=300)
        print(f"python {name}: Ctrl-C to KeyboardInterrupt {time.time() - sent:.2f} s "
              "(not asserted)")
        check(f"python {name}: interrupted", line.startswith("interrupted"), line)
        check(f"python {name}: no out", not os.path.exists(out))
        time.sleep(0.5)
        check(f"python {name}: no child left", not [k for k in kids if alive(k)], f"{kids}")


if __name__ == "__main__":
    main([shader_bounds, shader_text, orphans, python_cancel])
