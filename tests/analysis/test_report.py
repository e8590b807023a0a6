#!/usr/bin/python3
"""ctest: a small real sweep through pgt, then analysis/report.py and plot_summary.py must
produce non-empty figures and a report that embeds them. Arguments: PGT_BINARY SOURCE_DIR.
Exits 77 (skipped) only where matplotlib is missing."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

try:
    import matplotlib  # noqa: F401
    import pandas  # noqa: F401
except ImportError as e:
    print(f"skipped: {e.name} missing (apt-get install python3-matplotlib python3-pandas)")
    sys.exit(77)

pgt, source = sys.argv[1], sys.argv[2]
scene = {
    "heightmap": {"procedural": "bricks", "size": [32, 32]},
    "base": {"type": "plane", "infinite": True},
    "camera": {"type": "orthographic", "theta": 40, "frame": "fill", "resolution": [32, 32]},
    "methods": ["parallax", {"name": "pom", "min_layers": 4, "max_layers": 16}, "relief"],
    "truth": {"rate": 2},
    "sweep": {"theta": [0, 40, 70], "scale": [0.03, 0.06], "bias_ratio": [-1, -0.5, 0],
              "pom.max_layers": [8, 16], "timing": {"repeats": 1, "fragments": 128}},
}
failures = []
with tempfile.TemporaryDirectory() as d:
    path = os.path.join(d, "scene.json")
    json.dump(scene, open(path, "w"))
    out = os.path.join(d, "study")
    r = subprocess.run([pgt, "sweep", path, "--out", out], capture_output=True, text=True,
                       env={**os.environ, "PGT_ANALYSIS_DIR": os.path.join(source, "analysis")})
    if r.returncode != 0 or "report:" not in r.stdout:
        failures.append(f"pgt sweep: exit {r.returncode}\n{r.stdout}\n{r.stderr}")
    report = os.path.join(out, "report.md")
    text = open(report).read() if os.path.exists(report) else ""
    figures = [l.split("(")[1].rstrip(")") for l in text.splitlines() if l.startswith("![")]
    want = {"figures/error_vs_theta_s0.03.png", "figures/error_vs_theta_s0.06.png",
            "figures/pareto_ns.png", "figures/pareto_fetches.png",
            "figures/paper_error_vs_theta.png"}
    # The paper figure: every configuration on one axis per scale, as vectors too.
    if not os.path.getsize(os.path.join(out, "figures", "paper_error_vs_theta.svg")) > 0:
        failures.append("no paper_error_vs_theta.svg")
    if "for every configuration, one panel per scale" not in text:
        failures.append("the paper figure's caption is missing")
    if not want <= set(figures):
        failures.append(f"report.md lacks figures: {sorted(want - set(figures))}")
    for f in figures:
        p = os.path.join(out, f)
        if not os.path.exists(p) or os.path.getsize(p) < 5000:
            failures.append(f"figure missing or empty: {f}")
    if not any(f.startswith("figures/heatmap_pom") for f in figures):
        failures.append("no heat map for pom")
    if "| pom_4_16 |" not in text or "Welsh 2004" not in text:
        failures.append("defaults table missing rows or the documents' advice")
    # Every configuration in the ranking and the defaults table, each over the same cases;
    # no row without a document's advice reads "n/a".
    for label in ("parallax", "pom_4_8", "pom_4_16", "relief"):
        if not any(l.startswith("| ") and f"| {label} | 18 |" in l for l in text.splitlines()):
            failures.append(f"ranking lacks {label} over 18 cases")
        if f"| {label} | 0.03 |" not in text:
            failures.append(f"defaults table lacks {label}")
    if "over the 18 of 18 cases" not in text or "n/a" in text:
        failures.append("report does not say its 18 common cases, or has an n/a row")
    # The error per view angle as a table: a column per theta, a row per configuration, each
    # cell the mean of results.csv's means at that angle.
    if "| configuration | θ 0 | θ 40 | θ 70 |" not in text:
        failures.append("report lacks the table of error per view angle")
    rows = list(csv.DictReader(open(os.path.join(out, "results.csv"))))
    at70 = [float(r["mean"]) for r in rows if r["label"] == "relief" and float(r["theta"]) == 70]
    want70 = sum(at70) / len(at70)
    line = next((l for l in text.splitlines() if l.startswith("| relief | ")), "")
    cells = [c.strip() for c in line.strip("|").split("|")]
    if len(cells) != 4 or abs(float(cells[3]) - want70) > 1e-3 * want70:
        failures.append(f"angle table's relief row {line!r}: theta 70 should be {want70:.4g}")
    # A partial study (one configuration missing a case): every ranking over the 17 cases
    # all of them have, and said so.
    rows = list(csv.DictReader(open(os.path.join(out, "results.csv"))))
    partial = os.path.join(d, "partial")
    os.makedirs(partial)
    with open(os.path.join(partial, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(r for r in rows if not (r["label"] == "relief" and r["case"] == "5"))
    r = subprocess.run(["/usr/bin/python3", os.path.join(source, "analysis", "report.py"),
                        partial], capture_output=True, text=True)
    ptext = open(os.path.join(partial, "report.md")).read() if r.returncode == 0 else r.stderr
    if "over the 17 of 18 cases" not in ptext or "| pom_4_16 | 17 |" not in ptext:
        failures.append(f"partial study not ranked over its 17 common cases: {ptext[:400]}")
    # An accuracy-only study ("repeats": 0): no run-time figure, the report says why, and a
    # configuration equal to another in another panel is named "(= X)" in the table.
    def study_report(name, methods, sweep):
        """report.md of a sweep of the scene with these methods and sweep block (or stderr)."""
        path = os.path.join(d, name + ".json")
        json.dump(dict(scene, methods=methods, sweep=sweep), open(path, "w"))
        r = subprocess.run([pgt, "sweep", path, "--out", os.path.join(d, name)],
                           capture_output=True, text=True,
                           env={**os.environ, "PGT_ANALYSIS_DIR": os.path.join(source, "analysis")})
        return open(os.path.join(d, name, "report.md")).read() if r.returncode == 0 else r.stderr

    ftext = study_report("fast", ["parallax", {"name": "parallax", "label": "again"}],
                         {"theta": [0, 40], "timing": {"repeats": 0}})
    if "Nothing was timed" not in ftext or "pareto_ns" in ftext or "again (= parallax)" not in ftext:
        failures.append(f"accuracy-only report: {ftext[-600:]}")
    # A study of stored formats: the report's "Texture storage" table, each unorm row against
    # the float configuration with the same parameters (parallax's error added by unorm8 on
    # this constant-free map is not 0).
    stext = study_report("stored", ["parallax"],
                         {"theta": [40, 70], "parallax.format": ["float", "unorm8"],
                          "timing": {"repeats": 0}})
    row = next((l for l in stext.splitlines() if l.startswith("| parallax_u8 | unorm8 |")), "")
    if "## Texture storage" not in stext or row.count("(") != 2:
        failures.append(f"texture storage table: {row!r} in {stext[-800:]}")
    # plot_summary.py on one render of the same scene
    r = subprocess.run([pgt, "render", path, "--out", os.path.join(d, "frame")],
                       capture_output=True, text=True)
    png = os.path.join(d, "summary.png")
    r2 = subprocess.run(["/usr/bin/python3", os.path.join(source, "analysis", "plot_summary.py"),
                         os.path.join(d, "frame", "summary.json"), "--out", png],
                        capture_output=True, text=True)
    if r.returncode or r2.returncode or not os.path.exists(png) or os.path.getsize(png) < 5000:
        failures.append(f"plot_summary.py failed: {r.stderr} {r2.stderr}")
    # A report killed while it draws leaves no zero-byte or cut figure: each is written to a
    # hidden temporary and renamed. Killed at 24 times across its run.
    figdir = os.path.join(out, "figures")
    def gone_meanwhile(f, *args):
        """f(*args), or None where the file went (a killed report's worker gets its SIGKILL
        from the kernel a moment after the report: it may still rename or remove a temporary)."""
        try:
            return f(*args)
        except FileNotFoundError:
            return None

    for k in range(24):
        for name in os.listdir(figdir):
            gone_meanwhile(os.remove, os.path.join(figdir, name))
        p = subprocess.Popen(["/usr/bin/python3", os.path.join(source, "analysis", "report.py"),
                              out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(0.5 + 0.1 * k)
        p.kill()
        p.wait()
        for name in os.listdir(figdir):
            if name.startswith("."):
                continue  # a temporary the kill left; hidden, never a figure's name
            data = gone_meanwhile(lambda path: open(path, "rb").read(),
                                  os.path.join(figdir, name))
            if data is None:
                continue
            whole = (data.rstrip().endswith(b"</svg>") if name.endswith(".svg") else
                     data.startswith(b"\x89PNG") and data.endswith(b"IEND\xaeB`\x82"))
            if not whole:
                failures.append(f"killed at {0.5 + 0.1 * k:.2f} s: {name} is cut "
                                f"({len(data)} bytes)")
    # Every figure the report writes has a name it knows as its own (what it removes when a
    # later report does not write it again).
    sys.path.insert(0, os.path.join(source, "analysis"))
    from report import REPORT_FIGURES  # noqa: E402
    strays = [n for n in os.listdir(figdir) if not n.startswith((".",) + REPORT_FIGURES)]
    if strays:
        failures.append(f"figures not named in report.REPORT_FIGURES: {strays}")
    # --fresh into a directory holding another study: none of the earlier report's figures
    # stays (here the scale 0.06 the new study lacks); a file of the user's there stays.
    open(os.path.join(figdir, "mine.png"), "wb").write(b"\x89PNG not the report's")
    json.dump(dict(scene, sweep={"theta": [0, 40], "scale": [0.03], "timing": {"repeats": 0}}),
              open(path, "w"))
    r = subprocess.run([pgt, "sweep", path, "--out", out, "--fresh"], capture_output=True,
                       text=True,
                       env={**os.environ, "PGT_ANALYSIS_DIR": os.path.join(source, "analysis")})
    left = sorted(n for n in os.listdir(figdir) if "s0.06" in n or n.startswith("pareto_ns"))
    if (r.returncode != 0 or left or not os.path.exists(os.path.join(figdir, "mine.png"))
            or not os.path.exists(os.path.join(figdir, "error_vs_theta_s0.03.png"))):
        failures.append(f"--fresh left the earlier study's figures {left}: {r.stdout} {r.stderr}")
    # The report script's own exit status says why no report was written: 3, a plotting
    # package missing (pgt asks no second interpreter first); another, the script failed.
    for status, why in ((3, "matplotlib, pandas and numpy is needed"),
                        (1, "the report script failed")):
        fake = os.path.join(d, f"fake{status}")
        os.makedirs(fake)
        open(os.path.join(fake, "report.py"), "w").write(f"import sys\nsys.exit({status})\n")
        r = subprocess.run([pgt, "sweep", path, "--out", os.path.join(d, f"why{status}")],
                           capture_output=True, text=True,
                           env={**os.environ, "PGT_ANALYSIS_DIR": fake})
        if r.returncode != 0 or f"report not written: " not in r.stdout or why not in r.stdout:
            failures.append(f"report script exiting {status}: {r.returncode} {r.stdout} {r.stderr}")
# The report's PNG writer (common.write_png) against an independent decoder (PIL): the pixels
# Agg drew, RGB where every pixel is opaque and RGBA where one is not, and the figure's dpi.
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402
from common import plt as cplt, save_figure  # noqa: E402
with tempfile.TemporaryDirectory() as d:
    for alpha, mode in ((1.0, "RGB"), (0.5, "RGBA")):
        fig, ax = cplt.subplots(figsize=(2, 1.5), dpi=200)
        fig.patch.set_alpha(alpha)
        ax.plot([0, 1, 2], [1, 3, 2], marker="o")
        ax.set_title("a title")
        path = os.path.join(d, f"f{alpha}.png")
        save_figure(fig, path, fixed=True)
        fig.canvas.draw()
        drawn = np.asarray(fig.canvas.buffer_rgba())
        cplt.close(fig)
        im = Image.open(path)
        got = np.asarray(im)
        want = drawn if mode == "RGBA" else drawn[:, :, :3]
        if im.mode != mode or got.shape != want.shape or (got != want).any() \
                or abs(im.info.get("dpi", (0, 0))[0] - 200) > 0.01:
            failures.append(f"write_png, figure alpha {alpha}: {im.mode} {got.shape} "
                            f"{im.info} against {mode} {want.shape}")
# Ticks are made only where they are drawn (common._InView): a figure of shared log and linear
# panels saved by save_figure has the pixels of the same figure saved by matplotlib alone, with
# fewer tick objects made, and its locators are its own again afterwards.
with tempfile.TemporaryDirectory() as d:
    def panels():
        fig, axes = cplt.subplots(2, 2, figsize=(4, 3), dpi=200, sharex=True, sharey=True)
        for k, ax in enumerate(axes.flat):
            ax.plot([0, 10, 40, 80], [2e-5, 0.03 * (k + 1), 0.5, 40], marker="o")
            ax.set_yscale("log")
            ax.set_title(f"panel {k}")
        fig.subplots_adjust(left=0.15, bottom=0.12, top=0.9)
        return fig

    def ticks(fig):
        return sum(len(a.majorTicks) + len(a.minorTicks)
                   for ax in fig.axes for a in (ax.xaxis, ax.yaxis))

    plain, ours = panels(), panels()
    plain.savefig(os.path.join(d, "plain.png"), dpi=200)
    save_figure(ours, os.path.join(d, "ours.png"), fixed=True)
    a = np.asarray(Image.open(os.path.join(d, "plain.png")).convert("RGB"))
    b = np.asarray(Image.open(os.path.join(d, "ours.png")).convert("RGB"))
    kept = all(not type(t.locator).__name__.startswith("_")
               for ax in ours.axes for t in (ax.xaxis.major, ax.yaxis.major))
    if a.shape != b.shape or (a != b).any() or not ticks(ours) < ticks(plain) or not kept:
        failures.append(f"ticks in view: {a.shape} {b.shape} "
                        f"{int((a != b).any(axis=2).sum()) if a.shape == b.shape else ''} "
                        f"pixels differ; {ticks(ours)} tick objects against {ticks(plain)}; "
                        f"locators restored: {kept}")
# The angle figures of a study's scales drawn into one set of axes (fig_error_vs_theta) have
# the pixels of each scale drawn into axes of its own, in either order: panels of one, two and
# five lines (bands only up to four), spans of many decades and of one (minor ticks kept).
import pandas as pd  # noqa: E402
from report_configs import fig_error_vs_theta  # noqa: E402
from common import panel_legend  # noqa: E402
rows = []
for scale, spread in ((0.02, 1e4), (0.05, 3.0), (0.1, 1e2)):
    for method, labels in (("parallax", ["parallax", "welsh"]), ("pom", ["pom"]),
                           ("relief", [f"relief_{k}" for k in range(5)])):
        for k, label in enumerate(labels):
            for theta in (0, 30, 60, 80):
                mean = 1e-3 * (1 + k) * spread ** (theta / 80) * (1 + scale)
                rows.append({"method": method, "label": label, "scale": scale,
                             "bias_ratio": -0.5, "theta": theta, "mean": mean,
                             "p50": 0.7 * mean, "p90": 1.6 * mean})
angles = pd.DataFrame(rows)
scales = sorted(angles["scale"].unique())
with tempfile.TemporaryDirectory() as d:
    for name, order in (("up", scales), ("down", scales[::-1])):
        os.makedirs(os.path.join(d, name))
        fig_error_vs_theta(angles, os.path.join(d, name), order)
    for scale in scales:
        alone = os.path.join(d, f"alone{scale:g}")
        os.makedirs(alone)
        fig_error_vs_theta(angles, alone, [scale])
        want = np.asarray(Image.open(os.path.join(alone, f"error_vs_theta_s{scale:g}.png")))
        for name in ("up", "down"):
            got = np.asarray(Image.open(os.path.join(d, name, f"error_vs_theta_s{scale:g}.png")))
            if got.shape != want.shape or (got != want).any():
                failures.append(f"angle figure s = {scale:g}, scales drawn {name} in one set "
                                "of axes, differs from the figure drawn alone")
# A panel's legend (common.panel_legend) is left out only where it would repeat the title.
for labels, title, want in ((["pom"], "pom", False), (["pom", "pom_16"], "pom", True),
                            (["godot [b/s -1]"], "godot", True), ([], "none", False)):
    fig, ax = cplt.subplots()
    for label in labels:
        ax.plot([0, 1], [1, 2], label=label)
    panel_legend(ax, title)
    if (ax.get_legend() is not None) != want:
        failures.append(f"panel_legend({labels}, {title!r}): legend {not want}, expected {want}")
    cplt.close(fig)
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("14 passed, 0 failed")
