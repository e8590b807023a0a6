#!/usr/bin/python3
"""ctest: the report's per-preset and depth/shadow sections on synthetic results with known
answers: the surface a preset fits (the bias ratio of its lowest mean), its worst view angle,
its largest defect (non-finite pixels first, then texels moved head-on, then the growth with
the angle), the depth table's ranking and the shadow shares, the per-angle tables' intervals
over replicate seeds, the ranking's intervals and median run time, complete seeds only, t past
its table, and no heat map for one bias ratio. Arguments: PGT_BINARY SOURCE_DIR."""
import json
import os
import sys
import tempfile

try:
    import matplotlib  # noqa: F401
    import pandas as pd
except ImportError:
    print("skipped: python3-pandas or python3-matplotlib missing")
    sys.exit(77)

sys.path.insert(0, os.path.join(sys.argv[2], "analysis"))
from report_depth import depth_shadow_lines  # noqa: E402
from report_configs import angle_table_lines, own_surface  # noqa: E402
from report_engines import engine_lines  # noqa: E402


def rows():
    out = []
    for label, method, preset in (("pom", "pom", None), ("shifty", "shifty", "shifty"),
                                  ("nanny", "nanny", "nanny"), ("calm", "calm", "calm")):
        params = json.dumps({"preset": preset} if preset else {"precision": "float"})
        if label == "calm":  # its engine expresses b = -s only
            params = json.dumps({"preset": preset, "bias_per_scale": -1.0})
        for theta in (0, 40, 80):
            for ratio in (-0.5, -1.0):
                mean = {"pom": 0.1, "calm": 0.2 + theta / 10 + (ratio == -0.5) * 5}.get(label, 2.0)
                if label == "shifty" and theta == 0:
                    mean = 3.0  # moves texels head-on
                nonfinite = 7 if label == "nanny" and theta == 0 else 0
                depth = 0.2 if label == "pom" else float("nan")
                out.append({"case": 0, "theta": theta, "phi": 0, "scale": 0.05,
                            "bias": ratio * 0.05, "bias_ratio": ratio, "method": method,
                            "label": label, "params": params, "mean": mean, "ns_per_px": 10.0,
                            "nonfinite": nonfinite, "depth_mean": depth, "depth_p90": depth,
                            "depth_signed_mean": depth, "light_theta": 45.0, "light_phi": 0.0,
                            "shadow_disagree": 0.25 if label == "pom" else float("nan"),
                            "shadow_disagree_uv_right": 0.1, "shadow_disagree_uv_wrong": 0.5,
                            "truth_shadowed": 0.3})
    return pd.DataFrame(out)


failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


df = rows()
lines = engine_lines(df)
table = {l.split("|")[1].strip(): [c.strip() for c in l.split("|")[1:-1]]
         for l in lines if l.startswith("| ") and not l.startswith("| preset")}
check("pom" not in table, "a built-in is not a preset")
check(table["calm"][2] == "-1", f"calm fits b/s -1, got {table['calm']}")
check(table["calm"][4] == "80" and table["calm"][5] == "8.2", f"calm's worst angle: {table['calm']}")
check("grows to 8.2 texels at theta 80" in table["calm"][8], f"calm's defect: {table['calm']}")
check("non-finite uv' on 14 pixels (view angles 0)" in table["nanny"][8],
      f"nanny's defect: {table['nanny']}")
check("moves texels head-on (3 texels" in table["shifty"][8], f"shifty's defect: {table['shifty']}")
check(table["calm"][1] == "-1" and table["shifty"][1] == "the case's",
      f"the b/s each runs at: {table['calm']}, {table['shifty']}")

# A preset at a fixed b/s is measured on its own surface only, and says so in its label.
restricted, renamed = own_surface(df)
check(renamed == {"calm": "calm [b/s -1]"}, f"renamed: {renamed}")
check(set(restricted[restricted["label"] == "calm [b/s -1]"]["bias_ratio"]) == {-1.0},
      "calm keeps only its own surface's cases")
check(len(restricted[restricted["label"] == "pom"]) == len(df[df["label"] == "pom"]),
      "a built-in keeps every case")
elsewhere, renamed = own_surface(df[df["bias_ratio"] == -0.5])
check(renamed == {"calm": "calm [runs at b/s -1]"} and len(elsewhere) == len(df) // 2,
      f"no case on its surface: every case kept, and said: {renamed}")
check(engine_lines(df[df["label"] == "pom"]) == [], "no preset: no section")

with tempfile.TemporaryDirectory() as figdir:
    depth = depth_shadow_lines(df, figdir)
    text = "\n".join(depth)
    check("light at theta 45, phi 0" in text, "the light is named")
    check("| pom | 0.1 | 0.2 | 0.2 | 0.2 | 25.0% | 10.0% | 50.0% | 30.0% |" in text,
          "pom's depth and shadow row")
    check(os.path.exists(os.path.join(figdir, "depth_vs_theta.png")), "depth figure drawn")
    dark = df.drop(columns=[c for c in df.columns if c.startswith("depth")])
    check(depth_shadow_lines(dark, figdir) == [], "no depth columns: no section")

# The per-angle table with replicates: 1, 2, 3 texels over three seeds give 2 ± t(0.975, 2)
# / sqrt(3) = 2.484; one seed says that no interval is available; a table per scale.
reps = pd.DataFrame([{"label": "pom", "method": "pom", "theta": 40, "scale": s, "seed": seed,
                      "mean": float(seed), "params": "{}"}
                     for seed in (1, 2, 3) for s in (0.05, 0.1)])
text = "\n".join(angle_table_lines(reps))
check("| pom | 2 ± 2.5 |" in text and "95 % interval over the 3 replicate seeds" in text,
      f"intervals over replicates: {text}")
check("At scale s = 0.05 only:" in text and "At scale s = 0.1 only:" in text, text)
one = "\n".join(angle_table_lines(reps[reps["seed"] == 1]))
check("no interval is available" in one and "±" not in one, one)
# The ranking: each mean with its interval over the seeds, the run time the median over the
# cases of each case's median (one slow case does not move it), cases counted without seeds.
from common import seed_interval, t975  # noqa: E402
from report import configuration_table, ranking_table_lines  # noqa: E402
from report_configs import common_cases, fig_heatmaps  # noqa: E402

ranked = pd.DataFrame([{"case": 3 * (seed - 1) + k, "theta": 10 * k, "phi": 0, "scale": 0.05,
                        "bias": -0.025, "label": "a", "method": "a", "seed": seed,
                        "mean": float(seed), "p90": float(seed), "nonfinite": 0,
                        "ns_per_px": 100.0 if k == 2 else 10.0, "fetches_mean": 1.0,
                        "timing_backend": "cpu", "precompute_ms": 0.0}
                       for seed in (1, 2, 3) for k in range(3)])
agg = configuration_table(ranked)
check(agg["ns"].iloc[0] == 10.0 and agg["cases"].iloc[0] == 3,
      f"median time over cases, cases without seeds: {agg.to_dict('records')}")
text = "\n".join(ranking_table_lines(agg, {}, 3, float("nan")))
check("| 1 | a | 3 | 2 ± 2.5 | 2 ± 2.5 | 10 [10, 100] |" in text, text)
check(abs(t975(32) - 2.0395) < 1e-3 and abs(t975(41) - 2.0211) < 1e-3 and t975(1) != t975(1),
      "t beyond the table")
# A case missing at one seed is left out, so every seed averages the same cases.
torn = ranked[~((ranked["seed"] == 3) & (ranked["theta"] == 20))]
kept, n, total, _ = common_cases(torn)
check(n == 2 and total == 3 and set(kept["theta"]) == {0, 10}, f"kept {n} of {total}")
check(seed_interval(kept)[0] == 2.0, "the mean over complete seeds")
# One bias ratio: nothing to choose, no heat map.
with tempfile.TemporaryDirectory() as figdir:
    one_ratio = ranked.assign(bias_ratio=-0.5)
    check(fig_heatmaps(one_ratio, figdir) == [], "one bias ratio: no heat map")
    two = pd.concat([one_ratio, one_ratio.assign(bias_ratio=-1.0, bias=-0.05)])
    check(fig_heatmaps(two, figdir) == ["heatmap_a.png"], "two bias ratios: a heat map")
for f in failures:
    print("FAIL:", f)
print(f"{'ok' if not failures else 'failed'}: {len(failures)} failures")
sys.exit(1 if failures else 0)
