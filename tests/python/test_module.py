"""The Python module pgt against the CLI (run by ctest: python.module; docs/python.md).

Run as: /usr/bin/python3 -m pytest tests/python/test_module.py --pgt PGT --scenes SCENES
with the module on PYTHONPATH (the build tree's build/python, or an install's
lib/python3/dist-packages)."""

import ctypes
import ctypes.util
import json
import os
import platform
import subprocess
import threading
import time

import numpy as np
import OpenImageIO as oiio
import pytest

import pgt


def small_scene(scenes):
    """The default scene at 48x40 with a few methods (one GLSL preset), anchored in scenes/."""
    with open(os.path.join(scenes, "default.json")) as f:
        scene = json.load(f)
    scene["camera"]["resolution"] = [48, 40]
    scene["methods"] = ["parallax", {"name": "pom", "min_layers": 8, "max_layers": 32},
                        "maxmip", {"preset": "godot"}]
    scene["sweep"] = {"theta": [0, 60], "phi": [0], "scale": [0.05], "bias_ratio": [0, -0.5],
                      "resolution": [24, 24], "timing": {"repeats": 1, "fragments": 64,
                                                         "gl_fragments": 1024}}
    scene.pop("fit", None)
    return scene


def read_exr(path):
    img = oiio.ImageInput.open(path)
    assert img, oiio.geterror()
    spec = img.spec()
    pixels = img.read_image(oiio.FLOAT)
    img.close()
    return list(spec.channelnames), pixels


def without_timing(value):
    """summary.json without what differs between two runs of one scene: times, where the
    scene came from and what made the output (the command, the date)."""
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items()
                if not (k.endswith("_ms") or "ns_per" in k or "timing" in k
                        or k in ("scene_file", "provenance"))}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


@pytest.fixture(scope="module")
def cli_and_module(pgt_cli, scenes, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("frame")
    scene = small_scene(scenes)  # procedural: no file paths to anchor
    scene_file = tmp / "scene.json"
    scene_file.write_text(json.dumps(scene))
    cli_out = tmp / "cli"
    run = subprocess.run([pgt_cli, "render", str(scene_file), "--out", str(cli_out)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    frame = pgt.render(scene)
    return cli_out, frame, scene


def test_channels_equal_the_clis_frame_exr(cli_and_module):
    cli_out, frame, _ = cli_and_module
    names, pixels = read_exr(str(cli_out / "frame.exr"))  # OpenEXR sorts them by name
    assert sorted(frame.channels) == sorted(names)
    assert frame.pixels.dtype == np.float32 and frame.pixels.shape == pixels.shape
    for i, name in enumerate(names):
        a, b = frame[name], pixels[:, :, i]
        assert a.shape == (40, 48)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        assert np.array_equal(a[~np.isnan(a)], b[~np.isnan(b)]), name
    # Not vacuous: the methods moved the UV, and err holds real errors.
    assert np.nanmax(frame["pom.err"]) > 0
    assert not np.array_equal(frame["parallax.u"], frame["base.u"], equal_nan=True)
    assert "pom.err" in frame and frame.methods == ["parallax", "pom", "maxmip", "godot"]


def test_summary_is_summary_json(cli_and_module):
    cli_out, frame, _ = cli_and_module
    with open(cli_out / "summary.json") as f:
        cli = json.load(f)
    for m in cli["methods"]:
        m.pop("error_map")  # the module wrote no files
    assert without_timing(frame.summary) == without_timing(cli)
    assert frame.summary["methods"][1]["label"] == "pom"


def test_out_writes_the_clis_files(scenes, tmp_path):
    scene = dict(small_scene(scenes), methods=["parallax"])
    again = pgt.render(scene, tmp_path / "out")
    for name in ("frame.exr", "summary.json", "parallax_error.png"):
        assert (tmp_path / "out" / name).is_file(), name
    names, pixels = read_exr(str(tmp_path / "out" / "frame.exr"))
    assert sorted(names) == sorted(again.channels)
    for i, name in enumerate(names):
        assert np.array_equal(pixels[:, :, i], again[name], equal_nan=True), name
    assert again.summary["methods"][0]["error_map"]["file"] == "parallax_error.png"


def test_bad_input_raises_with_the_clis_message(pgt_cli, scenes, tmp_path):
    scene = small_scene(scenes)
    scene["camera"]["theta"] = 95
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(scene))
    run = subprocess.run([pgt_cli, "render", str(bad), "--out", str(tmp_path / "o")],
                         capture_output=True, text=True)
    assert run.returncode == 2
    message = run.stderr.strip().removeprefix("pgt: error: ")
    with pytest.raises(pgt.InputError) as caught:
        pgt.render(str(bad))
    assert str(caught.value) == message
    assert "camera.theta" in message
    assert isinstance(caught.value, ValueError)
    with pytest.raises(pgt.InputError, match="heightmap"):
        pgt.render({**scene, "heightmap": {"file": "no_such_map.png"}}, base_dir=tmp_path)
    with pytest.raises(TypeError):
        pgt.render(42)


def test_a_missing_image_module_raises_and_is_tried_again(scenes, tmp_path):
    """A map in a format other than PNG, EXR or TIFF needs lib/pgt/pgt_image.so
    (docs/install.md): a missing one named by
    PGT_IMAGE_MODULE is an InputError naming it, and setting the variable right afterwards in
    the same process is enough (a fresh interpreter: the module loads once per process)."""
    scene = small_scene(scenes)
    scene["methods"] = ["parallax"]
    # A PGM: PNG, EXR and TIFF maps are read without the module.
    ramp = tmp_path / "ramp.pgm"
    ramp.write_bytes(b"P5 16 16 255\n" + bytes((x * 16 + y) % 256
                                              for y in range(16) for x in range(16)))
    scene["heightmap"] = {"file": str(ramp)}
    code = f"""
import os, pgt
scene = {scene!r}
os.environ["PGT_IMAGE_MODULE"] = {str(tmp_path / "missing.so")!r}
try:
    pgt.render(scene, timing_repeats=1, timing_fragments=64)
    raise SystemExit("no error")
except pgt.InputError as e:
    assert "PGT_IMAGE_MODULE" in str(e) and "missing.so" in str(e), str(e)
del os.environ["PGT_IMAGE_MODULE"]
frame = pgt.render(scene, timing_repeats=1, timing_fragments=64)
assert frame.summary["methods"][0]["label"] == "parallax"
print("ok")
"""
    run = subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stdout + run.stderr


def test_unwritable_out_raises_output_error(scenes, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(pgt.OutputError):
        pgt.render(small_scene(scenes), blocker / "out")


def test_the_gil_is_released_while_pgt_works(scenes):
    """A Python thread keeps running while render works: with the GIL held it could not."""
    scene = small_scene(scenes)
    scene["camera"]["resolution"] = [160, 160]
    scene["methods"] = [{"name": "pom", "min_layers": 64, "max_layers": 64}]
    done = threading.Event()
    ticks = []

    def work():
        pgt.render(scene)
        done.set()

    start = time.perf_counter()
    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.002)
    t.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.1, "render too short to tell"
    # Held GIL: no ticks until the end. Released: a tick every few ms all along.
    gaps = np.diff([start] + ticks)
    assert len(ticks) > 10 and gaps.max() < elapsed / 2, (len(ticks), gaps.max(), elapsed)


def test_sweep_returns_results_csv(scenes, tmp_path):
    import pandas
    out = tmp_path / "study"
    results = pgt.sweep(small_scene(scenes), out, report=False)
    on_disk = pandas.read_csv(out / "results.csv")
    assert isinstance(results, pandas.DataFrame)
    pandas.testing.assert_frame_equal(results, on_disk)
    assert len(results) == 4 * 4  # 2 theta x 2 bias, 4 methods
    assert set(results["method"]) == {"parallax", "pom", "maxmip", "godot"}
    assert results.attrs["pgt"]["finished"] and results.attrs["pgt"]["run"] == 4
    again = pgt.sweep(small_scene(scenes), out, report=False)
    assert again.attrs["pgt"]["resumed"] == 4 and again.attrs["pgt"]["run"] == 0


def test_compare_gives_the_clis_verdict(pgt_cli, scenes, tmp_path):
    scene = small_scene(scenes)
    scene["camera"]["samples"] = "jittered"
    scene["sweep"]["replicates"] = 2
    pgt.sweep(scene, tmp_path / "old", report=False)
    pgt.sweep(scene, tmp_path / "new", report=False)
    verdict = pgt.compare(tmp_path / "old", tmp_path / "new", out=tmp_path / "cmp", figures=False)
    assert verdict["regression"] is False
    assert all(c["verdict"] == "unchanged" for c in verdict["configurations"])
    assert set(verdict["cells"]["ratio"]) == {1.0}  # the same seeds: every ratio exactly 1
    cli = subprocess.run([pgt_cli, "compare", tmp_path / "old", tmp_path / "new", "--out",
                          tmp_path / "cli"], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    with open(tmp_path / "cli" / "compare.json") as f:
        assert json.load(f)["configurations"] == verdict["configurations"]
    with pytest.raises(pgt.InputError, match="--bands"):
        pgt.compare(tmp_path / "old", tmp_path / "new", out=tmp_path / "bad", bands=[30, 10])
    with pytest.raises(pgt.InputError, match="replicates"):
        one = dict(scene, sweep=dict(scene["sweep"], replicates=1))
        pgt.sweep(one, tmp_path / "one", report=False)
        pgt.compare(tmp_path / "one", tmp_path / "new", out=tmp_path / "bad")


def test_a_dicts_relative_paths_start_at_base_dir(scenes, tmp_path):
    with open(os.path.join(scenes, "stones_pinhole.json")) as f:
        scene = json.load(f)
    scene["camera"]["resolution"] = [16, 16]
    scene["methods"] = ["parallax"]
    frame = pgt.render(scene, base_dir=scenes)  # maps/stones.png beside the bundled scenes
    assert frame["parallax.u"].shape == (16, 16)
    with pytest.raises(pgt.InputError, match="stones.png"):
        pgt.render(scene, base_dir=tmp_path)


def test_the_angle_plot_example_runs(scenes, tmp_path):
    """analysis/angle_plot.py (beside scenes/ in the source tree and in share/pgt)."""
    import matplotlib  # noqa: F401  (Debian's python3-matplotlib; the example needs it)
    script = os.path.join(scenes, os.pardir, "analysis", "angle_plot.py")
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(small_scene(scenes)))
    run = subprocess.run(["/usr/bin/python3", script, str(scene), "--out", str(tmp_path / "a.png"),
                          "--theta", "0", "70", "--resolution", "24", "--methods", "pom"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "a.png").stat().st_size > 1000


def test_timing_arguments_are_checked_as_the_cli_checks_them(scenes):
    """timing_repeats 0, -1 and 10**6 are refused as the CLI refuses them (nothing timed
    would be written as 0 ns/px; a million repeats would run for ever)."""
    scene = small_scene(scenes)
    for name, value in [("timing_repeats", 0), ("timing_repeats", -1),
                        ("timing_repeats", 10**6), ("timing_fragments", -1),
                        ("gl_timing_fragments", 0)]:
        with pytest.raises(pgt.InputError, match=f"{name} = {value}: expected an integer in"):
            pgt.render(scene, **{name: value})


def test_an_int_uniform_beyond_32_bits_is_refused(scenes):
    """3e9 and 2^53 written as integers set an int uniform, which holds 32 bits: refused as
    the CLI refuses them, naming methods[i].uniforms.NAME, the value and the range."""
    scene = small_scene(scenes)
    for value in (3000000000, 2**53):
        scene["methods"] = ["parallax", {"name": "mine", "glsl": "pgt:refined.glsl",
                                         "function": "SecantRelief",
                                         "uniforms": {"layers": value}}]
        with pytest.raises(pgt.InputError,
                           match=rf"methods\[1\]\.uniforms\.layers = {value}: .*2147483647"):
            pgt.render(scene)


def test_a_path_with_a_nul_is_refused(scenes, tmp_path):
    """A NUL would cut the path in C++ and read another file: refused, naming the path."""
    real = os.path.join(scenes, "default.json")
    with pytest.raises(pgt.InputError, match="NUL"):
        pgt.render(real + "\0.extra")
    with pytest.raises(pgt.InputError, match="NUL"):
        pgt.render(small_scene(scenes), out=str(tmp_path / "a\0b"))
    with pytest.raises(pgt.InputError, match="NUL"):
        pgt.sweep(real + "\0.extra", str(tmp_path / "study"))


def test_a_dict_over_the_scene_file_bound_is_refused(scenes):
    """A dict is JSON text handed over whole: over the 64 MiB a scene file may hold, it is
    refused as such a file is, before it is parsed."""
    scene = small_scene(scenes)
    scene["description"] = "x" * (65 << 20)
    with pytest.raises(pgt.InputError, match="more than the 67108864 accepted"):
        pgt.render(scene)


CTRL_C_CHILD = r"""
import json, os, sys, time
import pgt
scene = json.loads(sys.argv[1])
print("started", flush=True)
t0 = time.time()
try:
    pgt.render(scene, out=sys.argv[2])
    print("finished", flush=True)
except KeyboardInterrupt:
    print(f"interrupted {time.time() - t0:.3f}", flush=True)
"""


def render_in_a_child(scenes, out):
    """A Python child 1.5 s into a pgt.render (1536^2, pom 64-128) into `out`."""
    scene = small_scene(scenes)
    scene["camera"]["resolution"] = [1536, 1536]
    scene["methods"] = [{"name": "pom", "min_layers": 64, "max_layers": 128}]
    p = subprocess.Popen(["/usr/bin/python3", "-c", CTRL_C_CHILD, json.dumps(scene), str(out)],
                         stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.5)  # inside the render
    return p


def test_ctrl_c_stops_a_render_and_removes_its_out(scenes, tmp_path):
    """SIGINT during pgt.render raises KeyboardInterrupt and leaves no --out behind (the render
    created it). The outcome is asserted, not the latency: on a loaded machine the cancel flag's
    next poll may come later than a second (tests/bench/ctrl_c_latency.py measures it)."""
    out = tmp_path / "out"
    p = render_in_a_child(scenes, out)
    sent = time.time()
    p.send_signal(2)
    line = p.stdout.readline().strip()
    p.wait(timeout=30)
    assert line.startswith("interrupted"), line
    print(f"Ctrl-C to KeyboardInterrupt: {time.time() - sent:.3f} s (not asserted)")
    assert not out.exists(), os.listdir(out)


def test_sigterm_ends_python_without_leaving_its_out(scenes, tmp_path):
    """SIGTERM (its default action) ends the interpreter during pgt.render as it ends the CLI:
    by the signal, with the --out the render created removed and no temporary left."""
    out = tmp_path / "out"
    p = render_in_a_child(scenes, out)
    p.send_signal(15)
    assert p.wait(timeout=30) == -15
    assert not out.exists(), os.listdir(out)
    assert not [n for n in os.listdir(tmp_path) if ".pgt-tmp." in n]


def test_the_callers_floating_point_state_is_kept_and_does_not_change_results(scenes):
    """pgt's tracing threads set flush-to-zero and denormals-are-zero for Embree: the calling
    Python thread keeps its own state (a denormal stays a denormal, its rounding mode stays),
    and a caller's rounding mode does not reach pgt's numbers."""
    libm = ctypes.CDLL(ctypes.util.find_library("m"))
    fe_downward = {"x86_64": 0x400, "aarch64": 0x800000}.get(platform.machine())
    if fe_downward is None:
        pytest.skip(f"no FE_DOWNWARD value known for {platform.machine()}")
    scene = small_scene(scenes)
    tiny = np.array([1e-310])
    assert tiny[0] * 1.0 != 0.0
    reference = pgt.render(scene, timing_fragments=0).pixels
    assert libm.fesetround(fe_downward) == 0
    try:
        frame = pgt.render(scene, timing_fragments=0).pixels
        after = libm.fegetround()
    finally:
        libm.fesetround(0)
    assert after == fe_downward
    assert (tiny * 1.0)[0] == 1e-310, "denormals flushed in the calling thread"
    np.testing.assert_array_equal(frame, reference)
