#!/usr/bin/python3
"""ctest: analysis/compare.py exits 1 on a synthetic regression, 0 on an improvement and on
identical inputs, 2 on unusable input. Arguments: PGT_BINARY SOURCE_DIR."""
import os
import subprocess
import sys
import tempfile

try:
    import pandas as pd
except ImportError:
    print("skipped: python3-pandas missing")
    sys.exit(77)

source = sys.argv[2]
script = os.path.join(source, "analysis", "compare.py")


def study(scale_of_error):
    rows = []
    for theta in (0, 30, 60):
        for label, base in (("parallax", 1.0), ("pom_8_32", 0.1)):
            e = base * (1 + theta / 30) * scale_of_error.get(label, 1.0)
            rows.append({"case": 0, "theta": theta, "phi": 0, "scale": 0.05, "bias": -0.025,
                         "label": label, "mean": e, "p90": 2 * e})
    return pd.DataFrame(rows)


def run(old, new, *extra):
    with tempfile.TemporaryDirectory() as d:
        po, pn = os.path.join(d, "old.csv"), os.path.join(d, "new.csv")
        old.to_csv(po, index=False)
        new.to_csv(pn, index=False)
        r = subprocess.run(["/usr/bin/python3", script, po, pn, "--out", os.path.join(d, "cmp"),
                            *extra], capture_output=True, text=True)
        assert os.path.exists(os.path.join(d, "cmp", "compare.md")) or r.returncode == 2, r.stderr
        return r.returncode, r.stdout + r.stderr


failures = []
base = study({})
checks = [
    ("identical", base, base, [], 0),
    ("pom 10% worse", base, study({"pom_8_32": 1.10}), [], 1),
    ("pom 10% worse, tolerance 0.2", base, study({"pom_8_32": 1.10}), ["--tolerance", "0.2"], 0),
    ("pom 30% better", base, study({"pom_8_32": 0.7}), [], 0),
    ("p90 metric sees it too", base, study({"parallax": 1.5}), ["--metric", "p90"], 1),
]
for name, old, new, extra, want in checks:
    code, out = run(old, new, *extra)
    if code != want:
        failures.append(f"{name}: exit {code}, want {want}\n{out}")
with tempfile.TemporaryDirectory() as d:
    bad = os.path.join(d, "bad.csv")
    open(bad, "w").write("x,y\n1,2\n")
    r = subprocess.run(["/usr/bin/python3", script, bad, bad, "--out", d], capture_output=True)
    if r.returncode != 2:
        failures.append(f"bad input: exit {r.returncode}, want 2")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"{len(checks) + 1} passed, 0 failed")
