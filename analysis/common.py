"""Shared helpers for the analysis scripts: reading pgt's CSV and study.json, method
families, and the matplotlib setup. Runs on Debian's /usr/bin/python3."""
import contextlib
import json
import math
import os
import struct
import sys
import zlib

try:
    import matplotlib

    matplotlib.use("Agg")
    # SVG text as text (searchable, editable in a paper's figure, and 3x faster to write
    # than glyph outlines).
    matplotlib.rcParams["svg.fonttype"] = "none"
    # Titles at the axes' top (where matplotlib puts them when no tick labels are above the
    # axes, as in every figure here), not placed anew from the axes' measured extent at each
    # drawing: that measure was 0.2 s of a nine-panel figure's 0.65.
    matplotlib.rcParams["axes.titley"] = 1.0
    import matplotlib.backend_bases
    import matplotlib.pyplot as plt  # noqa: F401  (re-exported)
    import matplotlib.ticker
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    import numpy as np  # noqa: F401
    import pandas as pd
except ImportError as e:  # pragma: no cover - depends on the machine
    # Status 3 tells `pgt` (cli/report.cpp) that a package is missing, not that the script failed.
    print(f"{os.path.basename(sys.argv[0])}: {e.name or e} is missing or broken ({e}); install "
          "python3-matplotlib python3-pandas python3-numpy and run with /usr/bin/python3",
          file=sys.stderr)
    sys.exit(3)

# Where the documents put the bias, as a ratio b/s (docs/model.md §3): Welsh's ARB code
# b = -s/2; LearnOpenGL's depth map b = -s; Lengyel's signed height 2h - 1 is b = -s/2.
DOCUMENT_BIAS_RATIO = {
    "parallax": (-0.5, "Welsh 2004: b = -s/2"),
    "offset_limited": (-0.5, "Welsh 2004: b = -s/2"),
    "steep": (-1.0, "LearnOpenGL: b = -s"),
    "pom": (-1.0, "LearnOpenGL: b = -s"),
    "relief": (-1.0, "depth map as LearnOpenGL: b = -s"),
    "iterative": (-0.5, "Lengyel 2h - 1: b = -s/2"),
    "tangent_plane": (-0.5, "Lengyel 2h - 1: b = -s/2"),
}

KEYS = ["theta", "phi", "scale", "bias"]

# Student's t at 0.975 for 1-30 degrees of freedom (beyond: the normal's 1.96).
T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179,
        2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
        2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def t975(n):
    """Student's t at 0.975 for a mean of n values (n - 1 degrees of freedom); NaN below 2.
    Past the table, the Cornish-Fisher expansion about the normal's 1.96 (within 1e-4 there)."""
    if n < 2:
        return float("nan")
    if n - 2 < len(T975):
        return T975[n - 2]
    z, v = 1.959964, n - 1
    return z + (z ** 3 + z) / (4 * v) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * v * v)


def seed_interval(rows, column="mean"):
    """The mean of `column` over `rows` and the half-width of its 95 % interval over the
    replicate seeds: the rows averaged per seed (each seed has the same cases), then Student's
    t over the seeds' means. The half-width is NaN with one seed (no interval available)."""
    if "seed" not in rows.columns:
        rows = rows.assign(seed=1)
    per = rows.groupby("seed", dropna=False)[column].mean().dropna().to_numpy()
    if len(per) == 0:
        return float("nan"), float("nan")
    half = t975(len(per)) * per.std(ddof=1) / math.sqrt(len(per)) if len(per) > 1 else math.nan
    return float(per.mean()), float(half)


def label_halves(df, columns):
    """{label: [the half-width of each column's 95 % interval over the seeds]}: seed_interval
    for every configuration of a study at once."""
    return {label: [seed_interval(rows, c)[1] for c in columns]
            for label, rows in df.groupby("label")}


def plus_minus(value, half, digits=4):
    """"m ± h" (h to 2 significant digits), or "m" where no interval is available."""
    return nice(value, digits) + (f" ± {half:.2g}" if np.isfinite(half) else "")


def seed_count(df):
    """How many replicate seeds the study ran (1 for a study without the column)."""
    return int(df["seed"].nunique()) if "seed" in df.columns else 1


def interval_note(seeds):
    """How the report's intervals were made, or that none is available."""
    if seeds > 1:
        return (f"± is the half-width of the 95 % interval over the {seeds} replicate seeds "
                "(each seed's cases averaged, then Student's t over the seeds)")
    return ("one replicate per case, so no interval is available (give the sweep block "
            "\"replicates\": N for one)")


def case_keys(df):
    """The columns that identify a case: KEYS, and the light's angles where a study swept or
    set a light (a study without one has them empty; pandas drops empty keys when grouping)."""
    light = ["light_theta", "light_phi"]
    keys = list(KEYS)
    if all(c in df.columns for c in light) and df["light_theta"].notna().all():
        keys += light
    return keys


def _replace_whole(path, write):
    """Writes `path` whole or not at all: `write(tmp)` makes a hidden temporary beside it,
    which is renamed into place (a killed report leaves no zero-byte figure)."""
    directory, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(directory, f".{name}.pgt-tmp.{os.getpid()}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


# Every figure the reports write: 200 dots per inch, the canvas grown to whatever it holds
# (a title, a colour bar or a legend outside the axes is never clipped).
FIGURE_DPI = 200


def write_png(path, rgba, dpi):
    """An image (rows x columns x RGBA, uint8) as a PNG (a path or a binary file): RGB where
    every pixel is opaque, each row unfiltered, zlib at level 1, its resolution in dots per
    inch recorded (a paper's layout sizes the figure by it). PIL's encoder (matplotlib's)
    tries the row filters on every row, which these figures of flat colours and lines do not
    repay: over a 54-case report's figures it took 0.67 s of CPU against this writer's 0.37,
    and wrote 10 % more bytes."""
    rows, cols = rgba.shape[:2]
    opaque = bool((rgba[:, :, 3] == 255).all())
    pixels = rgba[:, :, :3] if opaque else rgba
    raw = np.empty((rows, 1 + pixels.shape[1] * pixels.shape[2]), np.uint8)
    raw[:, 0] = 0  # each row's filter: none
    # The pixels copied once, straight into the rows: setting .shape makes a view of them (or
    # raises), where reshape could copy the RGB slice first.
    body = raw[:, 1:]
    body.shape = pixels.shape
    body[...] = pixels

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", cols, rows, 8, 2 if opaque else 6, 0, 0, 0)
    per_metre = round(dpi / 0.0254)
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"pHYs", struct.pack(">IIB", per_metre, per_metre, 1))
            + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))
    if hasattr(path, "write"):
        path.write(data)
        return
    with open(path, "wb") as f:
        f.write(data)


class _PngCanvas(FigureCanvasAgg):
    """The Agg canvas with its PNGs written by write_png ("pgtpng": savefig's format)."""

    def print_pgtpng(self, filename_or_obj, **_):
        # savefig's other arguments (facecolor, ...) took effect before this call; PIL's
        # metadata and options have no use here (no "Software" text is written).
        FigureCanvasAgg.draw(self)
        write_png(filename_or_obj, np.asarray(self.buffer_rgba()), self.figure.dpi)


matplotlib.backend_bases.register_backend("pgtpng", _PngCanvas)


class _InView(matplotlib.ticker.Locator):
    """Another locator's ticks that fall in `axis`'s view. Matplotlib makes a tick object (two
    lines and a label, their properties copied) for every location a locator gives and then
    draws those in view; making them was most of a many-panel figure's drawing, and a locator
    gives a step or a decade beyond each end. The inner locator keeps its own axis (a log
    locator's spacing reads it)."""

    def __init__(self, inner, axis):
        self.inner = inner
        self.axis = axis

    def set_axis(self, axis):
        self.axis = axis

    def __call__(self):
        locs = np.asarray(self.inner(), dtype=float)
        # As Axis._update_ticks tests a tick, in the scale's coordinates, a little wider.
        scale = self.axis.get_transform()
        lo, hi = sorted(scale.transform(np.asarray(self.axis.get_view_interval(), dtype=float)))
        at = scale.transform(locs)
        slack = 1e-6 * (hi - lo)
        return locs[(at >= lo - slack) & (at <= hi + slack)]

    def tick_values(self, vmin, vmax):
        return self.inner.tick_values(vmin, vmax)

    def nonsingular(self, v0, v1):
        return self.inner.nonsingular(v0, v1)

    def view_limits(self, vmin, vmax):
        return self.inner.view_limits(vmin, vmax)

    def set_params(self, **kwargs):
        self.inner.set_params(**kwargs)


# Locators whose ticks depend on nothing but the view, and formatters that label a tick by its
# value alone: where an axis has only these, leaving out the ticks outside the view changes
# nothing drawn (an AutoMinorLocator spaces its ticks by the major ones; a FixedFormatter
# labels by position).
_FREE_LOCATORS = (matplotlib.ticker.MaxNLocator, matplotlib.ticker.LogLocator,
                  matplotlib.ticker.FixedLocator, matplotlib.ticker.MultipleLocator,
                  matplotlib.ticker.NullLocator)
_VALUE_FORMATTERS = (matplotlib.ticker.ScalarFormatter, matplotlib.ticker.LogFormatter,
                     matplotlib.ticker.FuncFormatter, matplotlib.ticker.StrMethodFormatter,
                     matplotlib.ticker.FormatStrFormatter, matplotlib.ticker.NullFormatter)


@contextlib.contextmanager
def _ticks_in_view(fig):
    """The figure's axes make tick objects only where ticks are drawn (_InView), where all
    of an axis's locators and formatters allow it; as they were afterwards."""
    wrapped = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            tickers = (axis.major, axis.minor)
            if any(isinstance(t.locator, _InView) for t in tickers) or not all(
                    isinstance(t.locator, _FREE_LOCATORS)
                    and isinstance(t.formatter, _VALUE_FORMATTERS) for t in tickers):
                continue  # wrapped already (a shared axis), or not safe to
            for ticker in tickers:
                if not isinstance(ticker.locator, matplotlib.ticker.NullLocator):
                    wrapped.append((ticker, ticker.locator))
                    ticker.locator = _InView(ticker.locator, axis)
    try:
        yield
    finally:
        for ticker, locator in wrapped:
            ticker.locator = locator


def save_figure(fig, path, fixed=False, **kwargs):
    """fig.savefig(path) written whole or not at all (its format from the path's ending), at
    FIGURE_DPI with nothing clipped unless `kwargs` says otherwise. `fixed`: the figure's
    margins were set to hold everything (subplots_adjust), so the canvas is not measured
    again (a second drawing pass). Ticks are made only where they are drawn (_InView); PNGs
    go through write_png."""
    fmt = os.path.splitext(path)[1].lstrip(".") or "png"
    kwargs = {"dpi": FIGURE_DPI, **({} if fixed else {"bbox_inches": "tight", "pad_inches": 0.05}),
              **kwargs}
    with _ticks_in_view(fig):
        _replace_whole(path, lambda tmp: fig.savefig(
            tmp, format="pgtpng" if fmt == "png" else fmt, **kwargs))


class _PlainLogFormatter(matplotlib.ticker.LogFormatter):
    """Log tick labels as plain numbers (1e-05, 0.01, 10), not mathtext: parsing 10^{-5} as
    TeX took a fifth of a report's drawing. Which ticks get a label is LogFormatter's choice."""

    def _num_to_string(self, x, vmin, vmax):
        return f"{x:g}"


def log_axis(ax, which="y"):
    """A log axis (call it once the data are drawn) labelled in plain numbers, with no minor
    ticks where it spans two decades or more: a figure of many panels spends a third of its
    time making the minor ticks of each, and the decades are labelled. A shorter span keeps
    them: its labels are on the minor ticks."""
    (ax.set_yscale if which == "y" else ax.set_xscale)("log")
    axis = ax.yaxis if which == "y" else ax.xaxis
    axis.set_major_formatter(_PlainLogFormatter())
    axis.set_minor_formatter(_PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(2, 0.4)))
    lo, hi = ax.get_ylim() if which == "y" else ax.get_xlim()
    if lo > 0 and hi >= 100 * lo:
        axis.set_minor_locator(matplotlib.ticker.NullLocator())


def panel_legend(ax, title, **kwargs):
    """A panel's legend (fontsize 6 unless `kwargs` says otherwise), left out where it would
    name one line as the panel's `title` already does."""
    labels = ax.get_legend_handles_labels()[1]
    if len(labels) > 1 or (labels and labels[0] != title):
        ax.legend(**{"fontsize": 6, **kwargs})


def widen_left_margin(fig, axes, pad=0.05):
    """Moves a figure's fixed left margin right where the y axes' tick and axis labels would
    pass the canvas's edge (`pad` inches kept): one measure of those axes, not of the figure."""
    renderer = fig.canvas.get_renderer()
    x0 = min(ax.yaxis.get_tightbbox(renderer).x0 for ax in axes)
    need = pad * fig.dpi - x0
    if need > 0:
        fig.subplots_adjust(left=fig.subplotpars.left + need / (fig.get_figwidth() * fig.dpi))


def write_text(path, text):
    """A text file written whole or not at all."""
    def write(tmp):
        with open(tmp, "w") as f:
            f.write(text)
    _replace_whole(path, write)


def read_results(path):
    df = pd.read_csv(path)
    if df.empty:
        sys.exit(f"{path}: no rows")
    return df


def read_study(directory):
    path = os.path.join(directory, "study.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def representative_labels(df, study):
    """One configuration per method name: the one the scene lists (before the sweep's
    parameter lists expanded it); the first label of that name otherwise."""
    reps = {}
    listed = []
    if study:
        for m in study["scene"]["methods"]:
            params = {k: v for k, v in m.items() if k not in ("name", "label")}
            listed.append((m["name"], params))
    for name in df["method"].drop_duplicates():
        rows = df[df["method"] == name][["label", "params"]].drop_duplicates("label")
        choice = rows["label"].iloc[0]
        for lname, params in listed:
            if lname != name:
                continue
            for label, p in zip(rows["label"], rows["params"]):
                if json.loads(p) == params:
                    choice = label
                    break
            break
        reps[name] = choice
    return reps


def nice(x, digits=4):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    return f"{x:.{digits}g}"
