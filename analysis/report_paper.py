"""The study report's paper figure (docs/outputs.md): every configuration (or, past 12, the
most accurate of each family) on one log axis against the view angle, one panel per scale,
with the 95 % interval over replicate seeds as a band where the study has replicates and the 1-texel
line; distinguishable in greyscale (line style, marker and grey level together); PNG at
200 dpi and SVG."""
import os

from common import log_axis, np, plt, save_figure, t975
from report_configs import families

LINES = ["-", "--", ":", "-."]
MARKS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def _labels(df):
    """Every configuration when there are at most 12; else each family's most accurate (the
    lowest mean error over the study's cases: the family at its best in this study)."""
    fams = families(df)
    every = [l for labels in fams.values() for l in labels]
    if len(every) <= 12:
        return every, "every configuration"
    means = df.groupby("label")["mean"].mean()
    return ([min(labels, key=lambda l: means.get(l, float("inf"))) for labels in fams.values()],
            "each family's most accurate configuration (lowest mean error over the cases)")


def _curve(sub):
    """Per theta: the mean over the cases and seeds, and the 95 % interval over the seeds
    taken on the log of the per-seed means (a band that stays positive on a log axis; NaN
    with one seed)."""
    per_seed = sub.groupby(["theta", "seed"])["mean"].mean().unstack("seed")
    mean = per_seed.mean(axis=1)
    logs = np.log(per_seed.clip(lower=1e-9))
    n = per_seed.notna().sum(axis=1)
    t = np.array([t975(int(k)) for k in n])
    half = t * logs.std(axis=1, ddof=1) / np.sqrt(n)
    centre = logs.mean(axis=1)
    return mean, np.exp(centre - half), np.exp(centre + half)


def fig_paper(df, figdir):
    """Writes figures/paper_error_vs_theta.{png,svg}; returns (png name, caption)."""
    if "seed" not in df.columns:
        df = df.assign(seed=1)
    labels, which = _labels(df)
    scales = sorted(df["scale"].unique())
    seeds = df["seed"].nunique()
    cols = min(3, len(scales))
    rows = (len(scales) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols + 1.6, 3.2 * rows), sharey=True,
                             squeeze=False)
    for ax in list(axes.flat)[len(scales):]:
        ax.set_visible(False)
    for ax, scale in zip(axes.flat, scales):
        sub = df[df["scale"] == scale]
        for i, label in enumerate(labels):
            mean, lo, hi = _curve(sub[sub["label"] == label])
            if mean.empty:
                continue
            grey = str(round(0.55 * (i % 4) / 3, 2))
            ax.plot(mean.index, mean.clip(lower=1e-6), color=grey, ls=LINES[i % len(LINES)],
                    marker=MARKS[i % len(MARKS)], ms=3.5, lw=1.1, label=label)
            if seeds > 1:
                ax.fill_between(mean.index, lo, hi, color=grey, alpha=0.15, lw=0)
        ax.axhline(1.0, color="k", lw=0.7, ls=(0, (6, 3)))
        log_axis(ax)
        ax.set_title(f"s = {scale:g}", fontsize=9)
        ax.set_xlabel("view angle θ [degrees]", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in axes[:, 0]:
        ax.set_ylabel("mean UV error [texels]", fontsize=8)
    legend = axes[0][cols - 1].legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                                      frameon=False)
    # Fixed margins in inches (neither format measures the canvas again): the panels keep
    # their width and the figure grows to the legend's measured width on the right, and to its
    # height below the top panel's top (a long list of configurations).
    panels = 3.6 * cols
    extent = legend.get_window_extent(fig.canvas.get_renderer())
    width = 0.75 + panels + 0.2 + extent.width / fig.dpi
    height = max(3.2 * rows, 0.3 + extent.height / fig.dpi + 0.15)
    fig.set_size_inches(width, height)
    fig.subplots_adjust(left=0.75 / width, right=(0.75 + panels) / width, bottom=0.5 / height,
                        top=1 - 0.3 / height, wspace=0.08, hspace=0.4)
    name = "paper_error_vs_theta"
    for ext in ("png", "svg"):
        save_figure(fig, os.path.join(figdir, f"{name}.{ext}"), fixed=True)
    plt.close(fig)
    band = (f"band: 95 % interval over the {seeds} replicate seeds (Student's t on the log of "
            "each seed's mean)" if seeds > 1 else
            "no band: one replicate per case (give the sweep block \"replicates\": N)")
    caption = (f"Mean error against view angle for {which}, one panel per scale, averaged over "
               f"every bias ratio and azimuth; {band}; dashed: 1 texel. "
               f"`figures/{name}.svg` is the same figure as vectors.")
    return f"{name}.png", caption
