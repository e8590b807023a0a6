#!/usr/bin/python3
"""Regression check between two pgt studies: OLD.csv and NEW.csv (results.csv files).

Cases are matched on (theta, phi, scale, bias) and configurations on their label. For every
label in both, the chosen error statistic is averaged over the matched cases; a label whose
average grew by more than --tolerance (relative, 0.05 = 5%) and more than --floor texels is
a regression. Writes DIR/compare.md and DIR/compare_<label>.png (old vs new across theta).
Exit status: 0 no regression, 1 regression, 2 bad input.
Usage: /usr/bin/python3 analysis/compare.py OLD.csv NEW.csv --out DIR [--tolerance 0.05]"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import KEYS, case_keys, nice, pd, plt, save_figure, write_text  # noqa: E402


def plot_label(grp, label, args, worse, growth):
    """One configuration's old and new error against view angle."""
    m_old, m_new = args.metric + "_old", args.metric + "_new"
    by_theta = grp.groupby("theta")[[m_old, m_new]].mean()
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(by_theta.index, by_theta[m_old], marker="o", label="old")
    ax.plot(by_theta.index, by_theta[m_new], marker="s", label="new")
    ax.set_yscale("log")
    ax.set_xlabel("view angle theta [degrees]")
    ax.set_ylabel(f"{args.metric} UV error [texels]")
    ax.set_title(f"{label}: {'REGRESSION' if worse else 'ok'} ({growth:+.1%})")
    ax.legend()
    fig.tight_layout()
    save_figure(fig, os.path.join(args.out, f"compare_{label}.png"), dpi=100)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--out", required=True)
    ap.add_argument("--tolerance", type=float, default=0.05, help="allowed relative growth")
    ap.add_argument("--floor", type=float, default=1e-4,
                    help="growth below this many texels is never a regression (float noise)")
    ap.add_argument("--metric", default="mean", choices=["mean", "rms", "p50", "p90", "p99", "max"])
    args = ap.parse_args()
    try:
        old, new = pd.read_csv(args.old), pd.read_csv(args.new)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        print(f"compare.py: cannot read input: {e}", file=sys.stderr)
        return 2
    for name, df in (("OLD", old), ("NEW", new)):
        missing = [c for c in KEYS + ["label", args.metric] if c not in df.columns]
        if missing:
            print(f"compare.py: {name} lacks columns {missing}", file=sys.stderr)
            return 2
    os.makedirs(args.out, exist_ok=True)
    keys = case_keys(old) if case_keys(old) == case_keys(new) else KEYS
    merged = old.merge(new, on=keys + ["label"], suffixes=("_old", "_new"))
    if merged.empty:
        print("compare.py: OLD and NEW share no (case, label) rows", file=sys.stderr)
        return 2
    m_old, m_new = args.metric + "_old", args.metric + "_new"
    rows, regressions = [], []
    for label, grp in merged.groupby("label"):
        a, b = grp[m_old].mean(), grp[m_new].mean()
        growth = (b - a) / a if a > 0 else (0.0 if b <= a else float("inf"))
        worse = b - a > args.floor and b > a * (1 + args.tolerance)
        rows.append((label, len(grp), a, b, growth, worse))
        if worse:
            regressions.append(label)
        plot_label(grp, label, args, worse, growth)
    only_old = sorted(set(old["label"]) - set(new["label"]))
    only_new = sorted(set(new["label"]) - set(old["label"]))
    lines = ["# pgt comparison", "", f"OLD `{args.old}`, NEW `{args.new}`, metric `{args.metric}`, "
             f"tolerance {args.tolerance:g} (relative), floor {args.floor:g} texels.", "",
             "| configuration | cases | old | new | change | verdict |", "|---|---|---|---|---|---|"]
    for label, n, a, b, g, worse in rows:
        lines.append(f"| {label} | {n} | {nice(a)} | {nice(b)} | {g:+.1%} | "
                     f"{'REGRESSION' if worse else 'ok'} |")
        print(f"{label:24s} {n:5d} cases  old {nice(a):>10s}  new {nice(b):>10s}  {g:+8.1%}  "
              f"{'REGRESSION' if worse else 'ok'}")
    if only_old:
        lines += ["", "Only in OLD: " + ", ".join(only_old)]
        print("only in OLD: " + ", ".join(only_old))
    if only_new:
        lines += ["", "Only in NEW: " + ", ".join(only_new)]
    write_text(os.path.join(args.out, "compare.md"), "\n".join(lines) + "\n")
    if regressions:
        print(f"regression: {', '.join(regressions)}")
        return 1
    print("no regression")
    return 0


if __name__ == "__main__":
    sys.exit(main())
