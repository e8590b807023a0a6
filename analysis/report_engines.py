"""The report's section on presets (docs/methods.md "Engine presets"): per preset, the surface
its defaults fit best (bias ratio), where its error grows most (view angle), what it does
head-on, and its non-finite pixels: what each engine gets wrong and where. Figures: the report's error-against-angle
panels (one per preset)."""
import json
import math
import os

from common import interval_note, log_axis, nice, np, plt, plus_minus, save_figure, seed_count
from common import seed_interval
from report_configs import fixed_bias_ratio

MARKERS = ["o", "s", "^", "v", "D", "P", "X"]


def _is_preset(params):
    try:
        return "preset" in json.loads(params)
    except (TypeError, ValueError):
        return False


def _defect(r):
    """The largest defect a row of the per-preset table shows, in words."""
    found = []
    if r["nonfinite"] > 0:
        found.append((1e9, f"non-finite uv' on {int(r['nonfinite'])} pixels "
                           f"(view angles {r['nonfinite_thetas']})"))
    if np.isfinite(r["head_on"]) and r["head_on"] > 0.5:
        found.append((r["head_on"], f"moves texels head-on ({nice(r['head_on'])} texels at theta 0)"))
    found.append((r["worst"] / 10, f"error grows to {nice(r['worst'])} texels at theta "
                                   f"{nice(r['worst_theta'])}"))
    return max(found, key=lambda x: x[0])[1]


def _row(label, g):
    by_ratio = g.groupby("bias_ratio")["mean"].mean()
    ratio = by_ratio.idxmin()
    fit = g[g["bias_ratio"] == ratio]
    by_theta = fit.groupby("theta")["mean"].mean()
    bad = g[g["nonfinite"] > 0]
    fixed = fixed_bias_ratio(g["params"].iloc[0])
    worst = by_theta.idxmax()
    return {"label": label, "runs_at": "the case's" if fixed is None else nice(fixed),
            "ratio": ratio, "fit_mean": by_ratio.min(),
            "fit_mean_h": seed_interval(fit)[1],
            "worst_theta": worst, "worst": by_theta.max(),
            "worst_h": seed_interval(fit[fit["theta"] == worst])[1],
            "head_on": by_theta.get(0, float("nan")),
            "head_on_h": seed_interval(fit[fit["theta"] == 0])[1],
            "nonfinite": int(g["nonfinite"].sum()),
            "nonfinite_thetas": ", ".join(nice(t) for t in sorted(bad["theta"].unique()))}


def _fig_engines(presets, rows, figdir):
    """One panel per engine (the preset name before its first "_"), a line per preset: its
    mean error against view angle on the surface it fits best (its bias ratio)."""
    fit = {r["label"]: r["ratio"] for r in rows}
    engines = {}
    for label in fit:
        engines.setdefault(label.split("_")[0], []).append(label)
    cols = min(3, len(engines))
    nrows = math.ceil(len(engines) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 2.9 * nrows), squeeze=False,
                             sharey=True)
    for ax in axes.flat[len(engines):]:
        ax.set_visible(False)
    for ax, (engine, labels) in zip(axes.flat, engines.items()):
        for i, label in enumerate(labels):
            g = presets[(presets["label"] == label) & (presets["bias_ratio"] == fit[label])]
            r = g.groupby("theta")["mean"].mean()
            ax.plot(r.index, r.values.clip(1e-4), marker=MARKERS[i % len(MARKERS)], ms=3,
                    lw=max(0.8, 2.4 - 0.4 * i), label=f"{label} (b/s {nice(fit[label])})")
        log_axis(ax)
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_title(engine, fontsize=9)
        ax.tick_params(which="both", labelsize=7)
        ax.legend(fontsize=6)
    # Fixed margins in inches (tight_layout over a dozen panels costs seconds).
    width, height = 4.2 * cols, 2.9 * nrows
    fig.subplots_adjust(left=0.85 / width, right=1 - 0.1 / width, bottom=0.55 / height,
                        top=1 - 0.3 / height, hspace=0.35, wspace=0.1)
    fig.supxlabel("view angle theta [degrees]", fontsize=9, y=0.05 / height, va="bottom")
    fig.supylabel("mean UV error on the surface it fits best [texels]", fontsize=9,
                  x=0.05 / width, ha="left")
    name = "presets_vs_theta.png"
    save_figure(fig, os.path.join(figdir, name), fixed=True)
    plt.close(fig)
    return name


def engine_lines(df, figdir=None):
    """report.md's per-preset section (its figure drawn into `figdir` when given); [] when the
    study has no preset."""
    if "params" not in df.columns:
        return []
    presets = df[df["params"].map(_is_preset)]
    if presets.empty:
        return []
    rows = [_row(label, g) for label, g in presets.groupby("label", sort=False)]
    lines = ["## What each preset gets wrong, and where", "",
             "Per preset (an engine's or a document's parallax on the study's surfaces, its "
             "amplitude mapped from the case's s; `_shipped`: at the values its engine ships): "
             "the b/s it runs at (the case's, or the one its engine can express), the bias "
             "ratio b/s of the surface it fits best and its mean error there, the view angle "
             "where that error is largest, its error head-on, its non-finite pixels, and the "
             "largest of these defects; " + interval_note(seed_count(presets)) + ". The figure "
             "draws each preset's error against view angle on the surface it fits best, a panel "
             "per engine.", ""]
    if figdir and presets["theta"].nunique() > 1:  # one view angle: the table says it all
        name = _fig_engines(presets, rows, figdir)
        lines += [f"![{name}](figures/{name})", ""]
    lines += ["| preset | runs at b/s | fits b/s | mean there | worst theta | mean there | "
              "head-on | non-finite px | largest defect |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['label']} | {r['runs_at']} | {nice(r['ratio'])} | "
                     f"{plus_minus(r['fit_mean'], r['fit_mean_h'])} | {nice(r['worst_theta'])} | "
                     f"{plus_minus(r['worst'], r['worst_h'])} | "
                     f"{plus_minus(r['head_on'], r['head_on_h'])} | {r['nonfinite']} | "
                     f"{_defect(r)} |")
    lines.append("")
    return lines
