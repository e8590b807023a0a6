#!/usr/bin/python3
"""Report of a `pgt sweep` study directory: figures and DIR/report.md.

Figures: error against view angle per method (one per scale), error against run time and
against fetches with the Pareto front, bias-ratio x scale heat maps with the minimum marked,
and a table of recommended scale/bias defaults beside the source documents' advice.
Usage: /usr/bin/python3 analysis/report.py DIR"""
import gc
gc.disable()  # while the modules load: no garbage among their objects (gc.freeze below)
import argparse  # noqa: E402
import concurrent.futures  # noqa: E402
import ctypes  # noqa: E402
import multiprocessing  # noqa: E402
import math  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import DOCUMENT_BIAS_RATIO, nice, np, pd, plt, read_results, read_study  # noqa: E402
from common import case_keys, interval_note, save_figure, seed_count, seed_interval  # noqa: E402
from common import label_halves, log_axis, plus_minus, widen_left_margin, write_text  # noqa: E402
from report_configs import angle_table_lines, common_cases, fig_error_vs_theta  # noqa: E402
from report_paper import fig_paper  # noqa: E402
from report_configs import families, fig_heatmaps, own_surface, storage_lines  # noqa: E402
from report_depth import depth_shadow_lines  # noqa: E402
from report_engines import engine_lines  # noqa: E402

# What the imports made lives as long as the process (and its forked workers): collections
# leave it out and run every 50,000 new objects, not 700 (they took 8 % of the drawing).
gc.freeze()
gc.set_threshold(50000, 20, 100)
gc.enable()


# The beginnings of every figure's name the report writes (tests/analysis/test_report.py checks
# that each figure it writes has one): what it removes when an earlier report's figure was not
# written again (a scale the study no longer has, `pgt sweep --fresh` into the directory of
# another study). Other files in figures/ are the user's and stay.
REPORT_FIGURES = ("pareto_", "error_vs_theta_s", "heatmap_", "depth_", "shadow_",
                  "presets_vs_theta", "paper_error_vs_theta")


def report_figures(figdir):
    """The report's figures now in `figdir` (REPORT_FIGURES; links left out), by name: their
    inode numbers. Each figure is written to a temporary renamed over it (common.save_figure),
    so one written again has a new inode."""
    found = {}
    for name in os.listdir(figdir):
        path = os.path.join(figdir, name)
        if (name.startswith(REPORT_FIGURES) and name.endswith((".png", ".svg"))
                and not os.path.islink(path)):
            found[name] = os.stat(path).st_ino
    return found


def remove_stale_figures(figdir, before):
    """Removes the report's figures that were there `before` (report_figures) and were not
    written again since."""
    for name, inode in report_figures(figdir).items():
        if before.get(name) == inode:
            os.remove(os.path.join(figdir, name))


def pareto_front(points):
    """Indices of points not dominated in (x, y), both to be minimised; a point with a
    coordinate not measured (nan: an untimed method) is on no front."""
    finite = [i for i in range(len(points)) if all(math.isfinite(v) for v in points[i])]
    order = sorted(finite, key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def mark_precomputed(ax, agg, pts):
    """Circles precomputed methods: their per-pixel cost leaves out a build made once per map
    (its ms are in the ranking table)."""
    for i in np.flatnonzero(agg["precompute"].values > 0):
        ax.scatter([max(pts[i][0], 1e-2)], [pts[i][1]], s=90, facecolors="none",
                   edgecolors="k", lw=0.8)


def place_labels(ax, items, fontsize=7, color="k"):
    """Writes (text, x, y) beside their points, each moved down in steps of a line until it
    clears the labels placed before it (in display pixels), so that none overlaps another; a
    label that would run past the axes' right edge goes on its point's left. The figure's
    margins are fixed before (the labels are not measured again)."""
    ax.autoscale_view()  # the final axes limits: transData maps them (no drawing pass)
    right = ax.get_window_extent().x1
    placed = []
    line = fontsize * 1.4
    for text, x, y in sorted(items, key=lambda t: (t[1], -t[2])):
        px, py = ax.transData.transform((max(x, 1e-2), y))
        width = 0.62 * fontsize * len(text)
        left = px + 4 + width > right
        lx = px - 4 - width if left else px + 4  # the label's left end
        dy = 4.0
        while any(abs(lx - qx) < max(width, qw) and abs(py + dy - qy) < line
                  for qx, qy, qw in placed):
            dy -= line
        placed.append((lx, py + dy, width))
        ax.annotate(text, (max(x, 1e-2), y), fontsize=fontsize, color=color,
                    textcoords="offset points", ha="right" if left else "left",
                    xytext=(-4 if left else 4, dy * 72 / ax.figure.dpi),
                    arrowprops=dict(arrowstyle="-", color="0.6", lw=0.4) if dy < 0 else None)


def configuration_table(df):
    """Per configuration: its mean and p90 error over the cases with the half-widths of their
    95 % intervals over the replicate seeds (common.seed_interval), its run time as the median
    over the cases of each case's median over its repeats (results.csv's ns_per_px) with the
    quartiles over the cases, its fetches, backend and precompute time."""
    agg = df.groupby(["label", "method"]).agg(
        mean=("mean", "mean"), p90=("p90", "mean"), ns=("ns_per_px", "median"),
        ns_q25=("ns_per_px", lambda x: x.quantile(0.25)),
        ns_q75=("ns_per_px", lambda x: x.quantile(0.75)),
        fetches=("fetches_mean", "mean"), backend=("timing_backend", "first"),
        precompute=("precompute_ms", "max")).reset_index()
    # Cases by their keys (a replicate's rows are one case at several seeds).
    cases = df[["label"] + case_keys(df)].drop_duplicates().groupby("label").size()
    agg["cases"] = agg["label"].map(cases)
    half = label_halves(df, ("mean", "p90"))
    agg["mean_h"] = agg["label"].map(lambda l: half[l][0])
    agg["p90_h"] = agg["label"].map(lambda l: half[l][1])
    return agg


def repeat_spread(df):
    """The repeats' own spread: the median over the timed rows of (p75 - p25) / median of a
    case's repeats (results.csv's ns_per_px_p25/p75), or NaN."""
    if not {"ns_per_px_p25", "ns_per_px_p75"} <= set(df.columns):
        return float("nan")
    rel = (df["ns_per_px_p75"] - df["ns_per_px_p25"]) / df["ns_per_px"]
    rel = rel[np.isfinite(rel)]
    return float(rel.median()) if len(rel) else float("nan")


def scatter_families(ax, agg, gl, xkey):
    """Each family's configurations at (agg[xkey], mean), GL ones as x, with the 95 % interval
    over the seeds as bars where the study has replicates (kept above 0 on the log axis)."""
    colours = plt.get_cmap("tab20")
    for k, (method, grp) in enumerate(agg.groupby("method")):
        x = grp[xkey].clip(lower=1e-2)
        ax.scatter(x, grp["mean"], label=method, s=22,
                   marker="x" if gl.loc[grp.index].all() else "o", color=colours(k % 20))
        half, y = grp["mean_h"].to_numpy(), grp["mean"].to_numpy()
        if np.isfinite(half).any():
            ax.errorbar(x, y, yerr=[np.minimum(half, 0.999 * y), half], fmt="none", lw=0.7,
                        color=colours(k % 20))


def label_pareto(ax, xkey, xlabel, bars):
    """A Pareto figure's axis labels, title and legend, its left margin grown to its y axis
    (long minor tick labels, 0.000115, on a short span)."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel("mean UV error over the cases [texels]")
    ax.set_title("error against " + ("run time" if xkey == "ns" else "fetches")
                 + (" (bars: 95 % interval over the replicate seeds)" if bars else ""))
    ax.legend(fontsize=6, ncol=2)
    widen_left_margin(ax.figure, [ax])


def fig_pareto(df, figdir):
    if "timing_backend" not in df.columns:  # studies written before GLSL methods existed
        df = df.assign(timing_backend="cpu")
    if "precompute_ms" not in df.columns:  # studies written before precomputed methods
        df = df.assign(precompute_ms=0.0)
    agg = configuration_table(df)
    gl = agg["backend"].astype(str) != "cpu"
    files = {}
    fronts = {}
    timed = np.isfinite(agg["ns"]).any()  # not in an accuracy-only study ("repeats": 0)
    for xkey, xlabel in [("ns", "method time [ns per pixel, median over the cases]: C++ single "
                                "thread (o), GL (x)"),
                         ("fetches", "height-map fetches per pixel")][0 if timed else 1:]:
        pts = [(x, y) for x, y in zip(agg[xkey], agg["mean"])]
        # GL times (another clock, all cores of a software GL or a GPU) are not on the same
        # axis as one C++ thread: the run-time front is over the C++ methods only.
        candidates = [i for i in range(len(pts)) if xkey != "ns" or not gl.iloc[i]]
        front = [candidates[i] for i in pareto_front([pts[i] for i in candidates])]
        fig, ax = plt.subplots(figsize=(8, 5.5))
        # Fixed margins in inches, set before the labels are placed in display pixels (the
        # canvas is measured by neither format): the y labels' room on the left, the x
        # label's below, the title's above.
        fig.subplots_adjust(left=0.8 / 8, right=1 - 0.15 / 8, bottom=0.55 / 5.5,
                            top=1 - 0.35 / 5.5)
        scatter_families(ax, agg, gl, xkey)
        fx = [pts[i][0] for i in front]
        fy = [pts[i][1] for i in front]
        ax.step([max(x, 1e-2) for x in fx], fy, where="post", color="k", lw=1,
                label="Pareto front" + (" (C++)" if xkey == "ns" else ""))
        if xkey == "ns" and gl.any():
            # The GL methods' own front: their times are the GL's (timer query on a GPU, the
            # wall clock of a software GL), on the same axis only as a second curve.
            gl_idx = [i for i in range(len(pts)) if gl.iloc[i]]
            gl_front = [gl_idx[i] for i in pareto_front([pts[i] for i in gl_idx])]
            ax.step([max(pts[i][0], 1e-2) for i in gl_front], [pts[i][1] for i in gl_front],
                    where="post", color="0.45", lw=1, ls="--", label="Pareto front (GL)")
            fronts["gl"] = [agg["label"].iloc[i] for i in gl_front]
        mark_precomputed(ax, agg, pts)
        log_axis(ax, "x")
        log_axis(ax)
        # The fronts' points are named (the GL front's in grey); every point is in the table.
        named = [(agg["label"].iloc[i], pts[i][0], pts[i][1]) for i in front]
        if xkey == "ns" and "gl" in fronts:
            named += [(l + " [GL]", pts[i][0], pts[i][1]) for i, l in
                      zip(agg.index[agg["label"].isin(fronts["gl"])],
                          agg["label"][agg["label"].isin(fronts["gl"])])]
        label_pareto(ax, xkey, xlabel, np.isfinite(agg["mean_h"]).any())
        place_labels(ax, named)
        name = f"pareto_{xkey}.png"
        save_figure(fig, os.path.join(figdir, name), fixed=True)
        save_figure(fig, os.path.join(figdir, f"pareto_{xkey}.svg"), fixed=True)
        plt.close(fig)
        files[xkey] = name
        fronts[xkey] = [agg["label"].iloc[i] for i in front]
    return agg, files, fronts


def defaults_table(df):
    """Per configuration and scale: the bias ratio with the lowest mean and p90 over the view
    angles, beside the ratio the source documents use for its method (where one does)."""
    rows = []
    for label in df["label"].drop_duplicates():
        sub = df[df["label"] == label]
        if sub["bias_ratio"].isna().all() or sub["bias_ratio"].nunique() < 2:
            continue
        name = sub["method"].iloc[0]
        for scale in sorted(sub["scale"].unique()):
            s = sub[sub["scale"] == scale].groupby("bias_ratio")[["mean", "p90"]].mean()
            if s.empty or not np.isfinite(s["mean"]).any():
                continue
            best_mean, best_p90 = s["mean"].idxmin(), s["p90"].idxmin()
            doc = DOCUMENT_BIAS_RATIO.get(name)
            doc_err = float("nan")
            if doc is not None:
                near = s.index[np.argmin(np.abs(s.index - doc[0]))]
                doc_err = s.loc[near, "mean"] if abs(near - doc[0]) < 1e-9 else float("nan")
            spread = (s["mean"].max() - s["mean"].min()) / s["mean"].min() if s["mean"].min() > 0 else float("nan")
            at = sub[sub["scale"] == scale]

            def half(ratio, column):  # the 95 % interval's half-width over the seeds
                if not np.isfinite(ratio):
                    return float("nan")
                return seed_interval(at[np.isclose(at["bias_ratio"], ratio)], column)[1]
            rows.append({"method": name, "label": label, "scale": scale, "spread": spread,
                         "ratio_mean": best_mean, "mean_at_best": s.loc[best_mean, "mean"],
                         "mean_at_best_h": half(best_mean, "mean"),
                         "ratio_p90": best_p90, "p90_at_best": s.loc[best_p90, "p90"],
                         "p90_at_best_h": half(best_p90, "p90"),
                         "doc_ratio": doc[0] if doc else float("nan"),
                         "doc_source": doc[1] if doc else "", "mean_at_doc": doc_err,
                         "mean_at_doc_h": half(doc[0], "mean") if np.isfinite(doc_err) else
                         float("nan")})
    return pd.DataFrame(rows)


def die_with_parent(parent):
    """A drawing worker dies with the report (Linux's PR_SET_PDEATHSIG): a report killed
    while it draws leaves no orphan still writing figures. A report killed between the fork and
    this call is already gone (`parent` is no longer the worker's parent): the worker leaves at
    once, or it would wait for work forever (seen: killed reports left such workers asleep)."""
    try:
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:
        os._exit(0)


def base_lines(base):
    """Which base surface, and for meshes which tangent frames and truth, the study used."""
    if base.get("type") == "gltf":
        return [f"Base: glTF asset `{base['source']}` ({base.get('part', '')}), drawn with "
                f"`{base.get('frames')}` tangent frames; truth `{base.get('truth_surface')}`."]
    if base.get("type") == "mesh":
        return [f"Base: mesh `{base['source']}` ({base.get('scheme')}, refine "
                f"{base.get('refine')}), drawn with pgt's Listing 7.4 tangent frames; truth "
                f"`{base.get('truth_surface')}`."]
    return []


def provenance_lines(directory):
    """What made the study (DIR/provenance.json, one entry per sweep or merge): pgt's version
    and commit, the machine, the Embree kernel, the GL, the date and the command."""
    path = os.path.join(directory, "provenance.json")
    try:
        with open(path) as f:
            runs = json.load(f)["runs"]
    except (OSError, ValueError, KeyError, TypeError):
        return ["Provenance: none recorded (no provenance.json: a study of an older pgt).", ""]
    lines = [f"Made by {len(runs)} run(s) (provenance.json):", ""]
    for r in runs[-8:]:
        p, m = r.get("pgt", {}), r.get("machine", {})
        gl = r.get("gl")
        lines.append(
            f"- {r.get('date', '?')}: pgt {p.get('version', '?')} commit {p.get('commit', '?')} "
            f"({p.get('build_type', '?')}, {p.get('compiler', '?')}); {m.get('cpu', '?')}, "
            f"{m.get('cores', '?')} cores, Embree kernel {m.get('embree_kernel', '?')}"
            + ("" if "huge_pages" not in m else
               ", huge pages" if m["huge_pages"] else ", 4 KB pages")
            + (f"; GL {gl.get('renderer', '?')} ({gl.get('version', '?')})" if gl else "")
            + (f"; {r['cases_run']} cases" if "cases_run" in r else "; did not finish")
            + f"; `{r.get('command', '?')}`")
    if len(runs) > 8:
        lines.append(f"- and {len(runs) - 8} earlier runs")
    return lines + [""]


def source_lines(df, study):
    """Each family's sources by their keys in docs/references.md (study.json's "sources", by
    configuration label); nothing for a study of an older pgt, which did not record them."""
    sources = (study or {}).get("sources")
    if not isinstance(sources, dict):
        return []
    cited = {}
    rows = df.drop_duplicates("label")
    for method, label, params in zip(rows["method"], rows["label"],
                                     rows.get("params", [None] * len(rows))):
        try:  # a preset is its own entry (its family is the built-in it stands for)
            method = json.loads(params).get("preset", method)
        except (TypeError, ValueError, AttributeError):
            pass
        for key in str(sources.get(label, "")).split():
            cited.setdefault(method, [])
            if key not in cited[method]:
                cited[method].append(key)
    if not cited:
        return []
    return ["Sources (keys of docs/references.md): "
            + "; ".join(f"`{m}` {', '.join(keys)}" for m, keys in cited.items()) + ".", ""]


def header_lines(df, study, directory):
    """The report's title, the study's scene and provenance, cases and the units."""
    cases = df[case_keys(df)].drop_duplicates()
    lines = ["# pgt study report", ""]
    if study:
        hm = study["scene"]["heightmap"]
        lines.append(f"Scene: `{hm['source']}` height map {hm['size'][0]}x{hm['size'][1]}, "
                     f"address `{study['scene']['address']}`, resolution "
                     f"{study['resolution'][0]}x{study['resolution'][1]}.")
        lines += base_lines(study["scene"].get("base", {}))
    lines += [""] + provenance_lines(directory) + source_lines(df, study)
    lines += [
        f"{len(cases)} cases (theta {', '.join(f'{t:g}' for t in sorted(df['theta'].unique()))}; "
        f"phi {', '.join(f'{p:g}' for p in sorted(df['phi'].unique()))}; "
        f"scale {', '.join(f'{s:g}' for s in sorted(df['scale'].unique()))}; "
        f"bias ratio {', '.join(f'{r:g}' for r in sorted(df['bias_ratio'].dropna().unique()))}) "
        f"x {df['label'].nunique()} method configurations = {len(df)} rows.",
        "",
        f"Truth uncertainty (rate vs 2 x rate), p99 over pixels: median over cases "
        f"{nice(df['truth_uncertainty_p99'].median())} texels, largest "
        f"{nice(df['truth_uncertainty_p99'].max())} texels. Errors below it are below the "
        "truth's own tessellation error.",
        "",
        "Errors are UV distances in texels (docs/model.md §7); run time is the method alone, "
        "single-threaded, on this machine's CPU; GLSL methods (marked GL) are timed by the GL "
        "named in results.csv's timing_backend, not comparable with one CPU thread.",
        ""]
    return lines


def ranking_note(n_common, n_total, flagged, renamed):
    """Which cases the figures and tables average over, who runs on its own surface only, and
    who had non-finite uv'."""
    lines = [f"Every figure, ranking and table below is over the {n_common} of {n_total} cases "
             "that every configuration finished with a finite mean error; a configuration's "
             "error is averaged over those same cases."]
    if renamed:
        lines += ["", "Presets marked `[b/s R]` run at b = R·s whatever the case's b (their "
                  "engine cannot express another: results.csv's `params` bias_per_scale, "
                  "docs/methods.md \"Engine presets\"); they are averaged over the cases whose "
                  "surface is at that b/s only, the surface they can be given (`[runs at b/s "
                  "R]`: the study has no such case, so every case counts, surfaces they were "
                  "not given included): "
                  + ", ".join(f"`{l}`" for l in renamed) + "."]
    if flagged:
        lines += ["", "Configurations marked ⚠ had pixels with a non-finite uv' (counted, never "
                  "averaged: see \"Stiff cases counted\") in some cases: "
                  + ", ".join(f"`{l}` ({n} cases)" for l, n in sorted(flagged.items())) + "."]
    return lines + [""]


def ranking_table_lines(agg, flagged, seeds, spread):
    """The ranking by mean error: each mean with its interval, each time a median with its
    quartiles over the cases."""
    lines = [f"Ranked by mean error; {interval_note(seeds)}. ns/px is the median over the cases "
             "of each case's median over its timing repeats (results.csv's ns_per_px), in "
             "brackets the quartiles over the cases; the fronts above use the same medians, so "
             "one slow case moves no configuration"
             + (f" (a case's repeats themselves spread by a median {spread:.1%} of their median, "
                "p25 to p75)" if np.isfinite(spread) else "") + ".", "",
             "| rank | configuration | cases | mean error | p90 | ns/px [q25, q75] | "
             "fetches/px | precompute ms |",
             "|---|---|---|---|---|---|---|---|"]
    for rank, (_, r) in enumerate(agg.sort_values("mean").iterrows(), 1):
        gl_mark = "" if str(r["backend"]) == "cpu" else " (GL)"
        pre = nice(r["precompute"], 3) if r["precompute"] > 0 else "—"
        flag = " ⚠" if r["label"] in flagged else ""
        ns = (f"{nice(r['ns'], 3)} [{nice(r['ns_q25'], 3)}, {nice(r['ns_q75'], 3)}]"
              if np.isfinite(r["ns"]) else "—")
        lines.append(f"| {rank} | {r['label']}{flag} | {int(r['cases'])} | "
                     f"{plus_minus(r['mean'], r['mean_h'])} | {plus_minus(r['p90'], r['p90_h'])} "
                     f"| {ns}{gl_mark} | {nice(r['fetches'], 3)} | {pre} |")
    return lines


def runtime_lines(theta_figs, angle_table, agg, pareto_files, fronts, flagged, paper=None,
                  ranking=()):
    """Error against view angle (figures and a table) and against run time, with the Pareto
    fronts and the table."""
    lines = ["## Error against view angle", ""]
    if paper:
        lines += [f"![all configurations against theta](figures/{paper[0]})", "", paper[1], ""]
    for scale, ratio, fname in theta_figs:
        lines += [f"![error vs theta, s = {scale:g}](figures/{fname})", ""]
    lines += angle_table
    lines += ["## Error against run time", ""]
    if "ns" in pareto_files:
        lines += [f"![error vs ns/px](figures/{pareto_files['ns']})", ""]
    else:
        lines += ["Nothing was timed (the study's `\"timing\": {\"repeats\": 0}`): error "
                  "against fetches only.", ""]
    lines += [f"![error vs fetches](figures/{pareto_files['fetches']})", ""]
    if "ns" in fronts:
        lines += ["Pareto front (mean error over the cases against the median ns/px): "
                  + ", ".join(f"`{l}`" for l in fronts["ns"]) + ".", ""]
    if "gl" in fronts:
        backends = sorted({str(b) for b in agg["backend"] if str(b) != "cpu"})
        lines += ["GL Pareto front (the GLSL methods against their GL time, dashed; "
                  + "; ".join(backends) + "): "
                  + ", ".join(f"`{l}`" for l in fronts["gl"]) + ".", ""]
    lines += ["Circled points are precomputed methods: their ns/px leaves out the build of "
              "their maps, made once per height map (precompute ms in the table). The fronts' "
              "points are named in the figures; every configuration is in the table.", ""]
    return lines + list(ranking)


def defaults_lines(table, table80, heat, seeds=1):
    """The scale and bias defaults, over all angles and up to 80 degrees, and the heat maps."""
    lines = ["", "## Scale and bias defaults", "",
             "For each configuration and scale: the bias ratio b/s with the lowest error "
             "averaged over the study's view angles, by mean and by p90, beside the ratio the "
             f"source documents use for its method (— where none does); {interval_note(seeds)}. "
             "Each interval is of its own ratio; the ratios share their seeds, so whether two "
             "differ is judged seed by seed (`pgt compare`'s paired test), not by whether their "
             "intervals overlap, and the best ratio's interval is optimistic (the same data "
             "chose it).", "",
             "| method | scale | best b/s (mean) | mean there | best b/s (p90) | p90 there | "
             "documents' b/s | mean there | spread of the mean over b/s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for _, r in table.iterrows():
        doc = f"{nice(r['doc_ratio'])} ({r['doc_source']})" if r["doc_source"] else "—"
        at_doc = plus_minus(r['mean_at_doc'], r['mean_at_doc_h']) if r['doc_source'] else '—'
        lines.append(f"| {r['label']} | {r['scale']:g} | {r['ratio_mean']:g} | "
                     f"{plus_minus(r['mean_at_best'], r['mean_at_best_h'])} | {r['ratio_p90']:g} | "
                     f"{plus_minus(r['p90_at_best'], r['p90_at_best_h'])} | {doc} | {at_doc} | "
                     f"{r['spread']:.1%} |")
    if table.empty:
        lines += ["(No configuration was run at two or more bias ratios: nothing to choose.)"]
    lines += ["", "A small spread means the bias hardly matters for that method (steep, pom and "
              "relief are translation-covariant in b on an infinite plane: what is left is the "
              "noise of the estimate), so the 'best' ratio there is not a recommendation."]
    if table80 is not None and not table80.empty:
        lines += ["", "The same over view angles up to 80 degrees only:", "",
                  "| method | scale | best b/s (mean) | mean there | best b/s (p90) | p90 there |",
                  "|---|---|---|---|---|---|"]
        for _, r in table80.iterrows():
            lines.append(f"| {r['label']} | {r['scale']:g} | {r['ratio_mean']:g} | "
                         f"{plus_minus(r['mean_at_best'], r['mean_at_best_h'])} | "
                         f"{r['ratio_p90']:g} | {plus_minus(r['p90_at_best'], r['p90_at_best_h'])} |")
    lines += [""]
    for fname in heat:
        lines += [f"![{fname}](figures/{fname})", ""]
    return lines


FRAME_NAMES = {"asset": "the asset's TANGENT", "mikktspace": "MikkTSpace",
               "pgt": "Listing 7.4/7.8"}


def frame_and_stiff_lines(df, frames="pgt"):
    """The tangent frame's share of the error (meshes; `frames`: which per-vertex frames the
    base was drawn with) and the stiff cases counted."""
    lines = []
    if "mean_exact_frame" in df.columns and df["mean_exact_frame"].notna().any():
        fr = df.groupby("label")[["mean", "mean_exact_frame"]].mean()
        lines += ["## Method error and tangent-frame error", "",
                  "Each method also ran with V in the exact frame of the drawn surface: the true "
                  "UV-space direction of the ray, from dS/du, dS/dv and l N (docs/model.md §2), "
                  "so UV shear and unequal scales count. Its error is the method's own (plus, on "
                  "a curved mesh, the bending within its march); the rest is what the per-vertex "
                  f"frame ({FRAME_NAMES.get(frames, frames)}) adds; "
                  + interval_note(seed_count(df)) + ".", "",
                  "| configuration | mean error | with exact frame | frame share |", "|---|---|---|---|"]
        halves = label_halves(df, ("mean", "mean_exact_frame"))
        for label, r in fr.iterrows():
            share = 1 - r["mean_exact_frame"] / r["mean"] if r["mean"] > 0 else float("nan")
            half = halves[label]
            lines.append(f"| {label} | {plus_minus(r['mean'], half[0])} | "
                         f"{plus_minus(r['mean_exact_frame'], half[1])} | {share:+.1%} |")
        lines.append("")
    bad = df.groupby("label")[["nonfinite", "zero_divide", "step_limit"]].sum()
    bad = bad[(bad > 0).any(axis=1)]
    if not bad.empty:
        lines += ["## Stiff cases counted", "", "| configuration | non-finite px | 0/0 or dot <= 0 | "
                  "step limit |", "|---|---|---|---|"]
        for label, r in bad.iterrows():
            lines.append(f"| {label} | {int(r['nonfinite'])} | {int(r['zero_divide'])} | "
                         f"{int(r['step_limit'])} |")
        lines.append("")
    if "warnings" in df.columns and df["warnings"].notna().any():
        lines += ["## Warnings", "", "Silent mistakes the frames showed (docs/outputs.md "
                  "\"Warnings\"): configuration, kind, cases.", "",
                  "| configuration | warning | cases |", "|---|---|---|"]
        w = df[df["warnings"].notna()]
        for (label, kinds), grp in w.groupby(["label", "warnings"]):
            lines.append(f"| {label} | {kinds} | {grp['case'].nunique()} |")
        lines.append("")
    return lines


def figure_pool():
    """Every figure is a job for two forked workers (one a core), the largest first, while
    the main process writes the tables: drawing is most of the report's time, and small jobs
    keep both cores busy to the end. An executor, not a multiprocessing.Pool: a worker that
    dies fails the report (BrokenProcessPool) instead of leaving it waiting for a result."""
    return concurrent.futures.ProcessPoolExecutor(
        2, mp_context=multiprocessing.get_context("fork"), initializer=die_with_parent,
        initargs=(os.getpid(),))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("dir", help="study directory (results.csv, study.json)")
    args = ap.parse_args()
    df = read_results(os.path.join(args.dir, "results.csv"))
    study = read_study(args.dir)
    figdir = os.path.join(args.dir, "figures")
    os.makedirs(figdir, exist_ok=True)
    earlier = report_figures(figdir)
    # Rankings and averages over the cases every configuration finished (a killed or partial
    # study has cases some configurations lack; a mean of different cases ranks nothing).
    common, n_common, n_total, flagged = common_cases(df)
    if common.empty:
        sys.exit(f"{args.dir}: no case that every configuration finished with a finite error")
    common, renamed = own_surface(common)
    flagged = {renamed.get(l, l): n for l, n in flagged.items()}

    pool = figure_pool()
    # One view angle draws no curve against it (a panel of single points): the tables say it.
    curves = common["theta"].nunique() > 1
    theta_job = pool.submit(fig_error_vs_theta, common, figdir) if curves else None
    depth_job = pool.submit(depth_shadow_lines, common, figdir)
    pareto_job = pool.submit(fig_pareto, common, figdir)
    paper_job = pool.submit(fig_paper, common, figdir) if curves else None
    engines_job = pool.submit(engine_lines, df, figdir)
    heat_jobs = [pool.submit(fig_heatmaps, common, figdir, [family])
                 for family in families(common)]
    table = defaults_table(common)
    write_text(os.path.join(args.dir, "defaults.csv"), table.to_csv(index=False))
    # Grazing views (the last few degrees) dominate means over all angles; the same table
    # over theta <= 80 shows the defaults for the views most frames contain.
    typical = common[common["theta"] <= 80]
    table80 = defaults_table(typical) if len(typical) and typical["theta"].nunique() < common["theta"].nunique() else None
    agg, pareto_files, fronts = pareto_job.result()
    paper = paper_job.result() if paper_job else None
    engines = engines_job.result()
    heat = [fig for job in heat_jobs for fig in job.result()]
    theta_figs = theta_job.result() if theta_job else []
    depth = depth_job.result()
    pool.shutdown()

    lines = (header_lines(df, study, args.dir) + ranking_note(n_common, n_total, flagged, renamed)
             + runtime_lines(theta_figs, angle_table_lines(common), agg, pareto_files, fronts,
                             flagged, paper,
                             ranking_table_lines(agg, flagged, seed_count(common),
                                                 repeat_spread(common)))
             + defaults_lines(table, table80, heat, seed_count(common))
             + engines
             + storage_lines(common)
             + depth
             + frame_and_stiff_lines(df, ((study or {}).get("scene", {}).get("base", {})
                                          .get("frames", "pgt"))))
    write_text(os.path.join(args.dir, "report.md"), "\n".join(lines))
    remove_stale_figures(figdir, earlier)
    print(f"wrote {os.path.join(args.dir, 'report.md')}")


if __name__ == "__main__":
    main()
    # Every file written and closed, the workers gone: no 0.1 s teardown of the modules.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
