#!/usr/bin/python3
"""Figures of a `pgt compare` directory (the verdict is pgt's: this script only draws it).

Reads DIR/compare.csv and DIR/history.csv and writes, under DIR/figures/ as PNG (200 dpi) and
SVG:
- ratio_<label>.png: per configuration, NEW / OLD against the view angle with its 95 %
  interval band, one line per scale, bands judged a regression marked with a filled red
  triangle, an improvement with an open green one (the last NEW against OLD);
- history.png: every configuration's error in each study (OLD first), with its 95 % interval
  over replicate seeds: the regression plot to keep in a paper or a CI dashboard.
Usage: /usr/bin/python3 analysis/compare.py DIR   (pgt compare runs it)"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import pd, plt, save_figure  # noqa: E402

# Line styles and markers that stay apart in greyscale.
STYLES = [("-", "o"), ("--", "s"), (":", "^"), ("-.", "D"), ((0, (5, 1, 1, 1)), "v"),
          ((0, (1, 1)), "P"), ((0, (8, 2)), "X"), ((0, (3, 1, 1, 1, 1, 1)), "*")]


def file_name(label):
    return re.sub(r"[^A-Za-z0-9_.-]", "_", label)


def save(fig, out, name):
    fig.tight_layout()
    for ext in ("png", "svg"):
        save_figure(fig, os.path.join(out, f"{name}.{ext}"))
    plt.close(fig)


def band_centre(df):
    return (df["theta_lo"] + df["theta_hi"]) / 2


def plot_ratio(cells, label, out):
    """One configuration: the ratio against theta per scale, its interval shaded."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for k, (scale, grp) in enumerate(cells.groupby("scale")):
        grp = grp.sort_values("theta_lo")
        x = band_centre(grp)
        ls, marker = STYLES[k % len(STYLES)]
        ax.plot(x, grp["ratio"], linestyle=ls, marker=marker, color="0.15", markersize=4,
                label=f"s {scale:g}")
        ax.fill_between(x, grp["ratio_lo"], grp["ratio_hi"], color="0.5", alpha=0.18, lw=0)
        worse, better = grp["change"] == "regression", grp["change"] == "improvement"
        ax.plot(x[worse], grp["ratio"][worse], "^", color="#c00000", markersize=9, zorder=5,
                label="regression" if k == 0 and worse.any() else None)
        ax.plot(x[better], grp["ratio"][better], "v", markerfacecolor="none",
                markeredgecolor="#007000", markersize=9, zorder=5,
                label="improvement" if k == 0 and better.any() else None)
    ax.axhline(1, color="0.4", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("view angle θ [degrees] (band centre)")
    ax.set_ylabel("error ratio NEW / OLD (95 % interval)")
    old, new = cells["label_old"].iloc[0], cells["label_new"].iloc[0]
    ax.set_title(label if old == new else f"{old} → {new}", fontsize=10)
    ax.legend(fontsize=8)
    save(fig, out, "ratio_" + file_name(label))


def plot_history(hist, out):
    """Every configuration across the studies, OLD first, on one log axis."""
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    names = hist.drop_duplicates("study").sort_values("study")
    for k, (label, grp) in enumerate(hist.groupby("label", sort=False)):
        grp = grp.sort_values("study")
        ls, marker = STYLES[k % len(STYLES)]
        shade = str(0.1 + 0.5 * (k % 4) / 4)
        ax.errorbar(grp["study"], grp["mean"],
                    yerr=[grp["mean"] - grp["lo"], grp["hi"] - grp["mean"]],
                    linestyle=ls, marker=marker, color=shade, capsize=3, markersize=4,
                    label=label)
    ax.set_xticks(names["study"], [os.path.basename(os.path.normpath(d)) or d
                                   for d in names["dir"]], rotation=20, ha="right", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("error [texels] (95 % interval over seeds)")
    ax.set_title("each configuration across the studies", fontsize=10)
    ax.legend(fontsize=7, ncol=2)
    save(fig, out, "history")


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    directory = sys.argv[1]
    try:
        cells = pd.read_csv(os.path.join(directory, "compare.csv"))
        hist = pd.read_csv(os.path.join(directory, "history.csv"))
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        print(f"compare.py: cannot read {directory}: {e}", file=sys.stderr)
        return 2
    out = os.path.join(directory, "figures")
    os.makedirs(out, exist_ok=True)
    if not cells.empty:
        last = cells[cells["study"] == cells["study"].iloc[-1]]
        for label, grp in last.groupby("label_old", sort=False):
            plot_ratio(grp, label, out)
    if not hist.empty:
        plot_history(hist, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
