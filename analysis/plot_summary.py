#!/usr/bin/python3
"""Plots one `pgt render` summary.json: per-method UV error (mean, p90, p99 in texels, log
scale) beside its cost (fetches and ns per pixel). Run with Debian's /usr/bin/python3."""
import argparse
import json
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("plot_summary.py: matplotlib is missing (apt-get install python3-matplotlib)")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("summary", help="summary.json written by pgt render")
    ap.add_argument("--out", required=True, help="output PNG")
    args = ap.parse_args()
    with open(args.summary) as f:
        s = json.load(f)

    methods = s["methods"]
    labels = [m["label"] for m in methods]
    floor = 1e-4  # log axis: errors below a ten-thousandth of a texel are drawn at the floor

    def stat(m, key):
        v = m["error_texels"][key]
        return max(v, floor) if v is not None else float("nan")

    fig, (ax, cost) = plt.subplots(1, 2, figsize=(12, 4.8), gridspec_kw={"width_ratios": [3, 2]})
    x = range(len(methods))
    width = 0.27
    for k, (key, colour) in enumerate([("mean", "#1f5fbf"), ("p90", "#e0a020"), ("p99", "#c03030")]):
        ax.bar([i + (k - 1) * width for i in x], [stat(m, key) for m in methods], width,
               label=key, color=colour)
    ax.set_yscale("log")
    ax.set_ylabel("UV error [texels]")
    ax.set_xticks(list(x), labels, rotation=30, ha="right")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.legend(title="error")
    view = s["view"]
    if view["type"] == "orthographic":
        where = f"theta {view['theta']}, phi {view['phi']}"
    else:
        where = f"pinhole, fov {view['fov']}"
    sc = s["scene"]["displacement"]
    unc = s["truth"].get("uncertainty", {})
    ax.set_title(f"{s['scene_file']}: {where}, s={sc['scale']}, b={sc['bias']}"
                 + (f"\ntruth uncertainty p99 {unc['p99_texels']:.4f} texels" if unc else ""),
                 fontsize=9)

    ns = [m["ns_per_px"] for m in methods]
    fetches = [m["fetches"]["mean"] for m in methods]
    means = [stat(m, "mean") for m in methods]
    cost.scatter(ns, means, color="#1f5fbf")
    for label, a, b, fch in zip(labels, ns, means, fetches):
        cost.annotate(f"{label} ({fch:.1f} fetch)", (a, b), fontsize=7,
                      textcoords="offset points", xytext=(4, 3))
    cost.set_xscale("log")
    cost.set_yscale("log")
    cost.set_xlabel("method time [ns per pixel, single thread]")
    cost.set_ylabel("mean UV error [texels]")
    cost.set_title("error against run time", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.out, dpi=200, bbox_inches="tight")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
