#!/usr/bin/python3
"""Error against view angle from pgt.render calls (docs/python.md): one frame per angle of a
scene, each method's mean and p90 error plotted against theta.

    PYTHONPATH=build/python /usr/bin/python3 analysis/angle_plot.py scenes/default.json \
        --out angle.png [--theta 0 20 40 60 70 80 85] [--resolution 128] [--methods pom maxmip]
"""
import argparse
import json
import os
import sys

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--out", required=True, help="the figure (PNG)")
    ap.add_argument("--theta", type=float, nargs="+", default=[0, 20, 40, 60, 70, 80, 85])
    ap.add_argument("--resolution", type=int, default=128)
    ap.add_argument("--methods", nargs="+", help="labels to keep (default: all)")
    args = ap.parse_args()

    import pgt
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with open(args.scene) as f:
        scene = json.load(f)
    scene["camera"]["resolution"] = [args.resolution, args.resolution]
    base = os.path.dirname(os.path.abspath(args.scene))
    errors = {}  # label -> [(mean, p90)] per theta
    for theta in args.theta:
        scene["camera"]["theta"] = theta
        frame = pgt.render(scene, base_dir=base, timing_repeats=1)
        for label in frame.methods:
            if args.methods and label not in args.methods:
                continue
            err = frame[label + ".err"]
            err = err[np.isfinite(err)]
            stats = (float(err.mean()), float(np.percentile(err, 90))) if err.size else (np.nan,) * 2
            errors.setdefault(label, []).append(stats)
        print(f"theta {theta:g}: {len(frame.methods)} methods", file=sys.stderr)

    fig, ax = plt.subplots(figsize=(8, 5))
    for label, stats in errors.items():
        mean = [s[0] for s in stats]
        line, = ax.plot(args.theta, mean, marker="o", label=label)
        ax.plot(args.theta, [s[1] for s in stats], ls=":", color=line.get_color())
    ax.set_yscale("log")
    ax.set_xlabel("view angle theta (degrees)")
    ax.set_ylabel("UV error (texels): mean, dotted p90")
    ax.set_title(os.path.basename(args.scene))
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(args.out, dpi=200, bbox_inches="tight")
    print(args.out)


if __name__ == "__main__":
    main()
