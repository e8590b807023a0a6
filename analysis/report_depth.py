"""The report's depth-offset and self-shadowing section (docs/model.md §7b): each
configuration's depth error and shadow disagreement against the view angle and against its
cost, beside its UV error. Studies without a light (or written before depth existed) have no
such columns, or only empty ones: the section is left out."""
import os

from common import interval_note, label_halves, log_axis, nice, np, plt, plus_minus, save_figure
from common import panel_legend, seed_count
from report_configs import families

MARKERS = ["o", "s", "^", "v", "D", "P", "X", "<", ">", "*"]

# (column, axis label, file stem)
MEASURES = [("depth_mean", "mean depth error [texels]", "depth"),
            ("shadow_disagree", "share of pixels whose shadow differs from the truth's", "shadow")]


def _save(fig, figdir, name, fixed=False):
    """Lays the figure out (unless its margins are `fixed`), writes figures/NAME, closes it;
    returns NAME."""
    if not fixed:
        fig.tight_layout()
    save_figure(fig, os.path.join(figdir, name), fixed=fixed)
    plt.close(fig)
    return name


def has_depth(df):
    return "depth_mean" in df.columns and np.isfinite(df["depth_mean"]).any()


def _panels(df, column, ylabel, figdir, stem):
    """One panel per family, a line per configuration: `column` averaged over the cases of
    each view angle."""
    fams = {f: ls for f, ls in families(df).items()
            if np.isfinite(df[df["label"].isin(ls)][column]).any()}
    if not fams or df["theta"].nunique() < 2:  # one view angle: a point, not a curve
        return None
    cols = min(3, len(fams))
    rows = (len(fams) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.0 * rows), squeeze=False)
    for ax in axes.flat[len(fams):]:
        ax.set_visible(False)
    for ax, (family, labels) in zip(axes.flat, fams.items()):
        for i, label in enumerate(labels):
            r = df[df["label"] == label].groupby("theta")[column].mean()
            r = r[np.isfinite(r)]
            if not r.empty:
                ax.plot(r.index, r.values, marker=MARKERS[i % len(MARKERS)], ms=3, lw=1.2,
                        label=label)
        if column == "depth_mean":
            log_axis(ax)
        ax.set_title(family, fontsize=9)
        ax.tick_params(which="both", labelsize=7)
        panel_legend(ax, family)
    # Fixed margins in inches (tight_layout over nine panels costs a second): the shared
    # labels' and the tick labels' room on the left and below, the panel titles' above.
    width, height = 4.2 * cols, 3.0 * rows
    fig.subplots_adjust(left=0.85 / width, right=1 - 0.1 / width, bottom=0.55 / height,
                        top=1 - 0.3 / height, hspace=0.35, wspace=0.25)
    fig.supxlabel("view angle theta [degrees]", fontsize=9, y=0.05 / height, va="bottom")
    fig.supylabel(ylabel, fontsize=9, x=0.05 / width, ha="left")
    return _save(fig, figdir, f"{stem}_vs_theta.png", fixed=True)


def _against_light(df, figdir):
    """Shadow disagreement against the light's angle, one line per C++ configuration (a study
    that swept light_theta)."""
    if "light_theta" not in df.columns or df["light_theta"].nunique() < 2:
        return None
    fig, ax = plt.subplots(figsize=(8, 5))
    colours = plt.get_cmap("tab20")
    for i, (label, grp) in enumerate(df.groupby("label", sort=False)):
        r = grp.groupby("light_theta")["shadow_disagree"].mean()
        r = r[np.isfinite(r)]
        if not r.empty:
            ax.plot(r.index, r.values, marker=MARKERS[i % len(MARKERS)], ms=3, lw=1.2,
                    color=colours(i % 20), label=label)
    ax.set_xlabel("light angle from the normal [degrees]")
    ax.set_ylabel("share of pixels whose shadow differs from the truth's")
    ax.legend(fontsize=6, ncol=2)
    return _save(fig, figdir, "shadow_vs_light_theta.png")


def _against_cost(agg, figdir):
    """Depth error and shadow disagreement against each configuration's median time (C++
    methods, the only ones that report depth); a measure the study has no value of (no light:
    no shadow) gets no panel."""
    measures = [m for m in MEASURES
                if (np.isfinite(agg[m[0]]) & np.isfinite(agg["ns"])).any()]
    if not measures:
        return None
    fig, axes = plt.subplots(1, len(measures), figsize=(5.5 * len(measures), 4.5),
                             squeeze=False)
    axes = axes[0]
    colours = plt.get_cmap("tab20")
    for ax, (key, ylabel, _) in zip(axes, measures):
        for k, (method, grp) in enumerate(agg.groupby("method")):
            ok = np.isfinite(grp[key]) & np.isfinite(grp["ns"])
            if ok.any():
                ax.scatter(grp["ns"][ok].clip(lower=1e-2), grp[key][ok], s=20, label=method,
                           color=colours(k % 20))
        log_axis(ax, "x")
        if key == "depth_mean":
            log_axis(ax)
        ax.set_xlabel("method time [ns per pixel, one C++ thread, median over the cases;\n"
                      "its shadow march left out]")
        ax.set_ylabel(ylabel)
        ax.tick_params(which="both", labelsize=7)
    axes[0].legend(fontsize=6, ncol=2)
    # Fixed margins in inches: the tick and axis labels' room on the left and below (the x
    # label has two lines).
    width = 5.5 * len(measures)
    fig.subplots_adjust(left=0.8 / width, right=1 - 0.15 / width, bottom=0.65 / 4.5,
                        top=1 - 0.15 / 4.5, wspace=1.0 / 5.5)
    return _save(fig, figdir, "depth_shadow_vs_cost.png", fixed=True)


def depth_shadow_lines(df, figdir):
    """report.md's section, its figures drawn into `figdir`; [] without depth columns."""
    if not has_depth(df):
        return []
    agg = df.groupby(["label", "method"], sort=False).agg(
        mean=("mean", "mean"), depth=("depth_mean", "mean"), depth_p90=("depth_p90", "mean"),
        signed=("depth_signed_mean", "mean"), shadow=("shadow_disagree", "mean"),
        right=("shadow_disagree_uv_right", "mean"), wrong=("shadow_disagree_uv_wrong", "mean"),
        truth=("truth_shadowed", "mean"), ns=("ns_per_px", "median")).reset_index()
    agg = agg.rename(columns={"depth": "depth_mean", "shadow": "shadow_disagree"})
    halves = label_halves(df, ("mean", "depth_mean", "depth_signed_mean"))
    agg["mean_h"] = agg["label"].map(lambda l: halves[l][0])
    agg["depth_h"] = agg["label"].map(lambda l: halves[l][1])
    agg["signed_h"] = agg["label"].map(lambda l: halves[l][2])
    figs = [_panels(df, col, ylabel, figdir, stem) for col, ylabel, stem in MEASURES]
    cost = _against_cost(agg, figdir)
    figs.append(_against_light(df, figdir))
    light = df[["light_theta", "light_phi"]].dropna().drop_duplicates()
    lit = ", ".join(f"theta {nice(t)}, phi {nice(p)}" for t, p in light.itertuples(index=False))
    lines = ["## Depth offset and self-shadowing", "",
             "Where each configuration puts the surface along the eye ray (its depth offset, "
             "docs/model.md §6c) against the truth's, in texels, and whether its shadow march "
             "agrees with the truth's shadow rays" + (f" (light at {lit})" if lit else
                                                      " (the study has no light)") + ". "
             "Signed mean > 0: the configuration puts the surface too deep. The shadow "
             "disagreement is split by whether the configuration's uv' was right (<= 1 texel) "
             "or wrong. GLSL methods report no depth and run no march (blank). "
             + "Means: " + interval_note(seed_count(df)) + ".", ""]
    for name in figs + [cost]:
        if name:
            lines += [f"![{name}](figures/{name})", ""]
    lines += ["| configuration | UV mean | depth mean | depth p90 | depth signed | shadow "
              "differs | where uv' right | where uv' wrong | truth in shadow |",
              "|---|---|---|---|---|---|---|---|---|"]
    for r in agg.sort_values("depth_mean", na_position="last").itertuples(index=False):
        pct = (lambda x: "" if not np.isfinite(x) else f"{x:.1%}")
        num = (lambda x: "" if not np.isfinite(x) else nice(x))
        pm = (lambda x, h: "" if not np.isfinite(x) else plus_minus(x, h))
        lines.append(f"| {r.label} | {pm(r.mean, r.mean_h)} | {pm(r.depth_mean, r.depth_h)} | "
                     f"{num(r.depth_p90)} | "
                     f"{pm(r.signed, r.signed_h)} | {pct(r.shadow_disagree)} | {pct(r.right)} | "
                     f"{pct(r.wrong)} | {pct(r.truth)} |")
    lines.append("")
    return lines
