"""pgt: Parallax Ground Truth from Python (docs/python.md).

    import pgt
    frame = pgt.render("scenes/default.json")          # a path, or the scene as a dict
    err = frame["pom.err"]                              # float32 H x W, texels (NaN: none)
    frame.summary["methods"][0]["error_texels"]["mean"] # summary.json as a dict
    results = pgt.sweep("scenes/default.json", "out/study")   # results.csv as a DataFrame
    verdict = pgt.compare("old/study", "new/study", out="cmp")   # pgt compare's verdict

Each call does what the CLI's command does (same scene format, same numbers, same files
when it writes any) with the GIL released while pgt works. Bad input raises pgt.InputError
(a ValueError) and an output that cannot be written pgt.OutputError (an OSError), each with
the CLI's message.
"""

import json
import os

from ._pgt import InputError, OutputError  # noqa: F401
from . import _pgt

__all__ = ["Frame", "render", "sweep", "compare", "InputError", "OutputError", "set_memory_limit_mb"]


class Frame:
    """One rendered view: frame.exr's channels and summary.json.

    channels: dict name -> float32 array (height x width), the names of frame.exr as pgt's
      channel schema makes them (docs/outputs.md: truth.u, truth.v, truth.hit, base.u, ...,
      LABEL.u, LABEL.v, LABEL.err per method, ...); row 0 is the top of the image, as in
      frame.exr. Views of one array: `pixels`.
    pixels: float32 array height x width x channels, in the channels' order.
    summary: summary.json as a dict.
    """

    def __init__(self, names, pixels, summary):
        self.pixels = pixels
        self.channels = {name: pixels[:, :, i] for i, name in enumerate(names)}
        self.summary = summary

    def __getitem__(self, name):
        return self.channels[name]

    def __contains__(self, name):
        return name in self.channels

    @property
    def methods(self):
        """The methods' labels, in the scene's order."""
        return [m["label"] for m in self.summary["methods"]]

    def __repr__(self):
        h, w, c = self.pixels.shape
        return f"<pgt.Frame {w}x{h}, {c} channels, methods {', '.join(self.methods)}>"


def _scene_arguments(scene, base_dir):
    """(file, text) for the extension: a path is read by pgt itself; a dict is sent as JSON
    text named '<scene dict>' in base_dir (default: the working directory), which anchors its
    relative paths (heightmap.file, base.file)."""
    if isinstance(scene, dict):
        base = os.fspath(base_dir) if base_dir is not None else os.getcwd()
        return os.path.join(base, "<scene dict>"), json.dumps(scene)
    if isinstance(scene, (str, os.PathLike)):
        return os.fspath(scene), ""
    raise TypeError(f"scene must be a path or a dict, not {type(scene).__name__}")


def render(scene, out=None, *, base_dir=None, timing_repeats=3, timing_fragments=65536,
           gl_timing_fragments=1 << 20):
    """Render one scene (`pgt render`): the truth, every method, their errors.

    scene: a scene file's path, or the scene as a dict (docs/scenes.md).
    out: also write the CLI's files there (frame.exr, summary.json, error maps).
    Returns a Frame."""
    file, text = _scene_arguments(scene, base_dir)
    names, pixels, summary = _pgt.render(file, text, os.fspath(out) if out is not None else "",
                                         timing_repeats, timing_fragments, gl_timing_fragments)
    return Frame(names, pixels, json.loads(summary))


def sweep(scene, out, *, base_dir=None, fresh=False, report=True, images=False,
          progress=False):
    """Run a study (`pgt sweep`), resuming one in `out` unless fresh=True.

    Returns results.csv as a pandas DataFrame; the run's summary (cases run and resumed,
    wall seconds, the report's path) is in its .attrs["pgt"]."""
    import pandas  # only the studies need it

    file, text = _scene_arguments(scene, base_dir)
    summary = _pgt.sweep(file, text, os.fspath(out), fresh, report, images, progress)
    results = pandas.read_csv(os.path.join(os.fspath(out), "results.csv"))
    results.attrs["pgt"] = summary
    return results


def compare(old, *new, out, metric="mean", bands=None, pairs=None, alpha=0.01,
            min_effect=0.05, floor=1e-4, any_scene=False, figures=True):
    """Judge NEW studies against OLD (`pgt compare OLD NEW... --out DIR`, docs/studies.md).

    bands: band edges in degrees ([0, 30, 60, 90]); default each theta its own band.
    pairs: {OLD_LABEL: NEW_LABEL} for renamed configurations.
    Returns compare.json as a dict (its "regression" is what the CLI's exit status says),
    with "cells": compare.csv as a pandas DataFrame."""
    import pandas

    if not new:
        raise TypeError("compare() needs OLD and at least one NEW study directory")
    dirs = [os.fspath(d) for d in (old, *new)]
    pair_list = list((pairs or {}).items())
    run = _pgt.compare(dirs, os.fspath(out), metric, list(bands or []), pair_list, alpha,
                       min_effect, floor, any_scene, figures)
    with open(os.path.join(os.fspath(out), "compare.json")) as f:
        verdict = json.load(f)
    verdict["cells"] = pandas.read_csv(os.path.join(os.fspath(out), "compare.csv"))
    verdict["figures_not_drawn"] = run["figures_not_drawn"]
    return verdict


def set_memory_limit_mb(mb):
    """Refuse inputs estimated to need more memory than this (the CLI's --memory-limit)."""
    _pgt.set_memory_limit_mb(mb)
