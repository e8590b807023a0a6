"""The small study the shard and Slurm tests split, and its rows compared without the measured
columns (ns_per_px and timing_backend may differ between runs)."""
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "analysis"))
from columns import without_measured  # noqa: E402

SCENE = {"heightmap": {"procedural": "bricks", "size": [16, 16], "jitter": 0.3, "seed": 3},
         "base": {"type": "plane", "infinite": True},
         "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [16, 16]},
         "methods": ["parallax", {"name": "pom", "min_layers": 4, "max_layers": 8}],
         "truth": {"rate": 1, "uncertainty": False},
         "sweep": {"theta": [0, 20, 40, 60, 80], "scale": [0.02, 0.05], "bias_ratio": [0, -0.5],
                   "pom.max_layers": [8, 16], "timing": {"repeats": 1, "fragments": 16}}}


def rows(directory):
    """DIR/results.csv without the measured columns, as a sorted list of tuples."""
    with open(os.path.join(directory, "results.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    return sorted(without_measured(r) for r in table)
