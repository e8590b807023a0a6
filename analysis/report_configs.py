"""The report's view of every configuration (docs/outputs.md "report.md"): configurations in
families (results.csv's `method`: a built-in's name, a GLSL/HLSL method's or preset's own),
the cases every configuration finished (rankings are over those only), and the figures drawn
as small multiples, one panel per family, so that no axes holds twenty lines and identical
curves stay visible."""
import json
import math
import os

from common import case_keys, interval_note, log_axis, nice, np, plt, plus_minus, save_figure
from common import panel_legend, seed_count
from common import seed_interval

MARKERS = ["o", "s", "^", "v", "D", "P", "X", "<", ">", "*"]
STYLES = ["-", "--", "-.", ":"]


def families(df):
    """{family: [labels in the order results.csv lists them]}."""
    out = {}
    for method, label in df[["method", "label"]].drop_duplicates("label").itertuples(index=False):
        out.setdefault(method, []).append(label)
    return out


def common_cases(df):
    """The rows of the cases every configuration finished with a finite mean at every replicate
    seed (so each seed's average is over the same cases), the number of those cases and of all
    cases, and {label: cases with non-finite uv'}."""
    keys = case_keys(df)
    seeded = keys + (["seed"] if "seed" in df.columns else [])
    labels = df["label"].nunique()
    finite = df[np.isfinite(df["mean"])]
    per_case = finite.groupby(seeded)["label"].nunique()
    good = per_case[per_case == labels].index
    rows = df.set_index(seeded).loc[good].reset_index() if len(good) else df.iloc[0:0]
    if "seed" in df.columns and len(rows):
        seeds = df["seed"].nunique()
        rows = rows[rows.groupby(keys)["seed"].transform("nunique") == seeds]
    total = len(df[keys].drop_duplicates())
    flagged = df[df["nonfinite"] > 0].groupby("label")["case"].nunique().to_dict()
    return rows, len(rows[keys].drop_duplicates()), total, flagged


def fixed_bias_ratio(params):
    """The b/s a configuration runs at whatever the case's b (params' `bias_per_scale`: a preset
    whose engine cannot express another b), or None."""
    try:
        r = json.loads(params).get("bias_per_scale")
    except (TypeError, ValueError, AttributeError):
        return None
    return None if r is None else float(r)


def own_surface(df):
    """Rows with each fixed-b configuration measured on its own surface only: a preset that runs
    at b/s = R whatever the case's b (fixed_bias_ratio) keeps the cases whose surface is at R,
    where the study has some, so it is ranked on the surface its engine can be given and not
    on surfaces it was never given. Its label gains " [b/s R]" (" [runs at b/s R]" where the
    study has no case at R: every case kept), so every table and figure says so beside its row.
    Returns the rows and {label: its new label}."""
    if "params" not in df.columns or "bias_ratio" not in df.columns or df.empty:
        return df, {}
    keep = np.ones(len(df), dtype=bool)
    renamed = {}
    for label, params in df.groupby("label", sort=False)["params"].first().items():
        ratio = fixed_bias_ratio(params)
        if ratio is None:
            continue
        rows = (df["label"] == label).values
        at = rows & (np.abs(df["bias_ratio"].values - ratio) < 1e-9)
        if at.all() or not rows.any() or at[rows].all():
            continue  # every case of it is on its own surface
        if at.any():
            keep &= ~(rows & ~at)
            renamed[label] = f"{label} [b/s {ratio:g}]"
        else:
            renamed[label] = f"{label} [runs at b/s {ratio:g}]"
    out = df[keep].copy()
    out["label"] = out["label"].replace(renamed)
    return out, renamed


def _grid(n):
    cols = min(3, n)
    return int(math.ceil(n / cols)), cols


def _duplicates(series):
    """{label: the earlier label whose curve equals it} among (label, values) pairs."""
    same = {}
    for i, (label, values) in enumerate(series):
        for earlier, other in series[:i]:
            if len(values) == len(other) and np.allclose(values, other, rtol=1e-9, atol=0,
                                                          equal_nan=True):
                same[label] = same.get(earlier, earlier)
                break
    return same


def _angle_series(sub, labels):
    series = []
    for label in labels:
        rows = sub[sub["label"] == label].groupby("theta")[["mean", "p50", "p90"]].mean()
        if not rows.empty:
            series.append((label, rows))
    return series


def _angle_panel(ax, sub, family, labels, same):
    """`same`: {label: the earlier label, in any panel, whose curve it equals}."""
    series = _angle_series(sub, labels)
    for i, (label, rows) in enumerate(series):
        # Earlier lines wider and under later ones: a curve equal to another still shows.
        name = label + (f" (= {same[label]})" if label in same else "")
        line, = ax.plot(rows.index, rows["mean"], marker=MARKERS[i % len(MARKERS)], ms=3,
                        ls=STYLES[i // len(MARKERS) % len(STYLES)],
                        lw=max(0.8, 3.0 - 0.35 * i), zorder=2 + i, label=name)
        if len(series) <= 4:
            ax.fill_between(rows.index, rows["p50"].clip(lower=1e-5),
                            rows["p90"].clip(lower=1e-5), color=line.get_color(), alpha=0.12)
    log_axis(ax)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.set_title(family, fontsize=9)
    ax.tick_params(which="both", labelsize=7)
    panel_legend(ax, family)


def _clear_angle_panel(ax):
    """Takes out what _angle_panel drew, keeping the axes and their tick objects (making those
    is most of a panel's cost): the next scale's figure draws into the same axes."""
    for artist in list(ax.lines) + list(ax.collections):
        artist.remove()
    if ax.get_legend() is not None:
        ax.get_legend().remove()
    ax.relim()
    ax.set_prop_cycle(None)  # the next lines take the colours from the first again


def _angle_figure(fams):
    """The axes of the angle figures, one panel per family, before any is drawn."""
    rows, cols = _grid(len(fams))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.1 * rows), sharex=True,
                             sharey=True, squeeze=False)
    for ax in list(axes.flat)[len(fams):]:
        ax.set_visible(False)
    for i, ax in enumerate(list(axes.flat)[:len(fams)]):
        if i + cols >= len(fams):  # the lowest panel of its column
            ax.set_xlabel("view angle theta [degrees]", fontsize=8)
            ax.tick_params(labelbottom=True)
    for ax in axes[:, 0]:
        ax.set_ylabel("UV error [texels]", fontsize=8)
    # Fixed margins (tight_layout over many panels costs seconds): 0.5 in below for the
    # axis label, 0.7 in above for the title and the panels' titles.
    height = 3.1 * rows
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.5 / height, top=1 - 0.7 / height,
                        hspace=0.3, wspace=0.08)
    return fig, axes


def fig_error_vs_theta(df, figdir, scales=None):
    """One figure per scale (at the bias ratio nearest -1/2; a preset kept to its own surface
    at that surface's): a panel per family with every configuration of it; mean error, and
    the p50..p90 band where a panel has few lines. `scales`: only these (the report draws
    each in a worker of its own). The scales' figures are drawn into one set of axes, one
    after another."""
    out = []
    ratios = sorted(df["bias_ratio"].dropna().unique())
    fams = families(df)
    fig = axes = None
    for scale in sorted(df["scale"].unique()) if scales is None else scales:
        sub = df[df["scale"] == scale]
        ratio = min(ratios, key=lambda r: abs(r + 0.5)) if ratios else float("nan")
        if ratios:
            # A preset kept to its own surface (own_surface: "[b/s R]") is drawn there.
            at = np.isclose(sub["bias_ratio"], ratio)
            sub = sub[at | ~sub["label"].isin(set(sub[at]["label"]))]
        # Equal curves are named across the panels, not only within one.
        everything = [s for labels in fams.values() for s in _angle_series(sub, labels)]
        same = _duplicates([(l, r["mean"].values) for l, r in everything])
        if fig is None:
            fig, axes = _angle_figure(fams)
        else:
            for ax in list(axes.flat)[:len(fams)]:
                _clear_angle_panel(ax)
        for ax, (family, labels) in zip(axes.flat, fams.items()):
            _angle_panel(ax, sub, family, labels, same)
        fig.suptitle(f"mean error against view angle, s = {scale:g}, b/s = {ratio:g} "
                     "(band: p50..p90; '(= X)': the same curve as X)", fontsize=10,
                     y=1 - 0.15 / fig.get_figheight())
        name = f"error_vs_theta_s{scale:g}.png"
        save_figure(fig, os.path.join(figdir, name), fixed=True)
        out.append((scale, ratio, name))
    if fig is not None:
        plt.close(fig)
    return out


def _angle_cells(df, order, thetas):
    """Per configuration and theta: the mean text, "m ± h" (95 % over seeds) with replicates."""
    seeds = seed_count(df)
    means = df.groupby(["label", "theta"])["mean"].mean().unstack("theta")
    cells = {(label, t): nice(m) for (label, t), m in means.stack().items()}
    if seeds > 1:
        for (label, t), rows in df.groupby(["label", "theta"]):
            cells[(label, t)] = plus_minus(*seed_interval(rows))
    rows = {label: [cells.get((label, t), nice(float("nan"))) for t in thetas] for label in order}
    return means, rows, seeds


def _angle_table(df, caption):
    means = df.groupby(["label", "theta"])["mean"].mean().unstack("theta")
    thetas = list(means.columns)
    order = [l for labels in families(df).values() for l in labels if l in means.index]
    same = _duplicates([(l, means.loc[l].values) for l in order])
    _, rows, _ = _angle_cells(df, order, thetas)
    lines = [caption, "", "| configuration | " + " | ".join(f"θ {t:g}" for t in thetas) + " |",
             "|---|" + "---|" * len(thetas)]
    for label in order:
        name = label + (f" (= {same[label]})" if label in same else "")
        lines.append(f"| {name} | " + " | ".join(rows[label]) + " |")
    return lines + [""]


def angle_table_lines(df):
    """Mean error (texels) per view angle for every configuration: over every scale, then at
    each scale; with replicate seeds each mean with its 95 % interval over the seeds."""
    how = interval_note(seed_count(df))
    lines = _angle_table(df, "Mean error in texels per view angle θ, over every scale, bias "
                         f"ratio and azimuth of the study; {how}; `(= X)`: the same numbers "
                         "as X.")
    scales = sorted(df["scale"].unique())
    if len(scales) > 1:
        for sc in scales:
            lines += _angle_table(df[df["scale"] == sc], f"At scale s = {sc:g} only:")
    return lines


def _heat_grid(sub):
    return sub.groupby(["scale", "bias_ratio"])["mean"].mean().unstack("bias_ratio")


def _heat_panel(ax, sub, label, limits):
    grid = _heat_grid(sub)
    data = np.log10(grid.values.clip(min=1e-5))
    im = ax.imshow(data, aspect="auto", origin="lower", cmap="viridis", vmin=limits[0],
                   vmax=limits[1])
    ax.set_xticks(range(grid.shape[1]), [f"{c:g}" for c in grid.columns], fontsize=6)
    ax.set_yticks(range(grid.shape[0]), [f"{r:g}" for r in grid.index], fontsize=6)
    for r in range(grid.shape[0]):
        if np.isfinite(grid.values[r]).any():
            # In the cell's corner, clear of its number.
            ax.plot(int(np.nanargmin(grid.values[r])) + 0.32, r + 0.28, marker="*",
                    color="red", ms=8)
        for k in range(grid.shape[1]):
            ax.text(k, r, nice(grid.values[r, k], 2), ha="center", va="center", fontsize=6,
                    color="w")
    ax.set_title(label, fontsize=8)
    return im


def fig_heatmaps(df, figdir, only=None):
    """Per family (or the families `only` names: the report draws them in several workers):
    a panel per configuration, its mean error over the view angles on the scale x bias-ratio
    grid (star: the minimum per scale)."""
    files = []
    for family, labels in families(df).items():
        if only is not None and family not in only:
            continue
        subs = [(l, df[df["label"] == l]) for l in labels]
        # A heat map chooses a bias: one bias ratio is one column, nothing to choose.
        subs = [(l, s) for l, s in subs if s["bias_ratio"].nunique() >= 2]
        if not subs:
            continue
        # One colour scale for the family's panels.
        logs = np.concatenate([np.log10(_heat_grid(s).values.clip(min=1e-5)).ravel()
                               for _, s in subs])
        limits = (np.nanmin(logs), np.nanmax(logs)) if np.isfinite(logs).any() else (None, None)
        rows, cols = _grid(len(subs))
        fig, axes = plt.subplots(rows, cols, figsize=(4.0 * cols, 2.8 * rows), squeeze=False)
        for ax, (label, sub) in zip(axes.flat, subs):
            im = _heat_panel(ax, sub, label, limits)
            ax.set_xlabel("bias ratio b/s", fontsize=7)
            ax.set_ylabel("scale s", fontsize=7)
        for ax in list(axes.flat)[len(subs):]:
            ax.set_visible(False)
        # Fixed margins in inches (the canvas is not measured again): the axis labels' room on
        # the left, the colour bar and its label's on the right.
        width, height = 4.0 * cols, 2.8 * rows
        fig.subplots_adjust(left=0.7 / width, right=1 - 1.3 / width, bottom=0.55 / height,
                            top=1 - 0.6 / height, hspace=0.6, wspace=0.3)
        fig.colorbar(im, cax=fig.add_axes([1 - 1.1 / width, 0.15, 0.12 / width, 0.7]),
                     label="log10 mean error [texels]")
        fig.suptitle(f"{family}: mean error over view angles (star: minimum per scale)",
                     fontsize=9, y=1 - 0.15 / height)
        fname = f"heatmap_{family}.png"
        save_figure(fig, os.path.join(figdir, fname), fixed=True)
        plt.close(fig)
        files.append(fname)
    return files


def storage_lines(df):
    """The error a stored format adds (results.csv's `params` "format": docs/methods.md "Texture
    storage"): each unorm configuration against the float one with the same parameters, mean
    error added per view angle over the study's scales and bias ratios, beside the float
    configuration's own error. Nothing where the study has no format."""
    def key(params):
        p = json.loads(params)
        fmt = p.pop("format", "float")
        p.pop("label", None)
        return fmt, json.dumps(p, sort_keys=True)

    keyed = df.assign(**dict(zip(["fmt", "pkey"], zip(*df["params"].map(key)))))
    if (keyed["fmt"] == "float").all():
        return []
    cols = ["case", "method", "pkey"]
    base = keyed[keyed["fmt"] == "float"][cols + ["label", "mean"]]
    extra = ["seed"] if "seed" in keyed.columns else []
    stored = keyed[keyed["fmt"] != "float"][cols + extra + ["label", "fmt", "theta", "mean"]]
    both = stored.merge(base, on=cols, suffixes=("", "_float"))
    if both.empty:
        return []
    both["added"] = both["mean"] - both["mean_float"]
    thetas = sorted(both["theta"].unique())
    lines = ["## Texture storage", "",
             "The mean error (texels) a stored format adds to the same configuration reading "
             "the float map, per view angle θ over every scale and bias ratio (the float "
             "configuration's own mean error in brackets): where the added error passes the "
             "method's own, the format costs more than the method; "
             + interval_note(seed_count(df)) + ".", "",
             "| configuration | format | " + " | ".join(f"θ {t:g}" for t in thetas) + " |",
             "|---|---|" + "---|" * len(thetas)]
    for (label, fmt), g in both.groupby(["label", "fmt"], sort=True):
        by = g.groupby("theta")[["added", "mean_float"]].mean()
        half = {t: seed_interval(rows, "added")[1] for t, rows in g.groupby("theta")}
        cells = [f"{plus_minus(by.loc[t, 'added'], half[t], 2)} ({nice(by.loc[t, 'mean_float'], 2)})"
                 if t in by.index else "—" for t in thetas]
        lines.append(f"| {label} | {fmt} | " + " | ".join(cells) + " |")
    return lines + [""]
