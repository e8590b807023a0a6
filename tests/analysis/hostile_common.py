"""The harness of the hostile-input tests (test_hostile.py, test_hostile_studies.py): the
pgt binary and source folder from the command line, checks counted and failures kept, and
the scenes they start from. Arguments of the scripts: PGT_BINARY SOURCE_DIR CLASS."""
import csv
import json
import os
import struct
import subprocess
import sys
import tempfile
import zlib

PGT, SRC, CLASS = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, os.path.join(SRC, "analysis"))
from columns import MEASURED_COLUMNS, without_measured  # noqa: E402,F401
GOOD = {"heightmap": {"procedural": "sine", "size": [8, 8]}, "base": {"type": "plane"},
        "camera": {"type": "orthographic", "theta": 30, "resolution": [8, 8]},
        "methods": ["parallax"], "truth": {"rate": 1}}
SWEEP = {"heightmap": {"procedural": "bricks", "size": [16, 16], "jitter": 0.3, "seed": 3},
         "base": {"type": "plane", "infinite": True},
         "camera": {"type": "orthographic", "theta": 30, "frame": "fill", "resolution": [16, 16]},
         "methods": ["parallax", {"name": "pom", "min_layers": 4, "max_layers": 8}],
         "truth": {"rate": 1, "uncertainty": False},
         "sweep": {"theta": [0, 20, 40, 60], "scale": [0.02, 0.05],
                   "timing": {"repeats": 1, "fragments": 16}}}
failures = []
checks = 0
# A build under AddressSanitizer (.ci/sanitize.sh): its shadow memory and quarantine inflate
# the resident set, so peak-memory bounds, which hold for the release build, are not checked.
with open(PGT, "rb") as _binary:
    SANITIZED = b"__asan_init" in _binary.read()


def copy(obj):
    return json.loads(json.dumps(obj))


def run(args, timeout=120, **kw):
    return subprocess.run([PGT] + args, capture_output=True, text=True, timeout=timeout, **kw)


def check(name, ok, detail=""):
    global checks
    checks += 1
    if not ok:
        failures.append(f"{name}: {detail}")


def expect_error(name, r, status, words, out=None):
    """One stderr line with every word, the status, and no output directory left behind."""
    lines = [l for l in r.stderr.splitlines() if l.strip()]
    ok = r.returncode == status and len(lines) == 1 and all(w in lines[0] for w in words)
    if out is not None:
        ok = ok and not os.path.exists(out)
    check(name, ok, f"exit {r.returncode} (want {status}), stderr {r.stderr[:600]!r}")


def write(d, name, text):
    path = os.path.join(d, name)
    mode = "wb" if isinstance(text, bytes) else "w"
    with open(path, mode) as f:
        f.write(text)
    return path


def png(width, height, rows=None, truncate=None):
    """A grey 8-bit PNG; `rows` None writes only the header chunk (a header-only file)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xffffffff)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
    if rows is not None:
        raw = b"".join(b"\x00" + bytes(r) for r in rows)
        out += chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
    else:  # a first IDAT (readers stop there for the header), then the end: no pixels
        out += chunk(b"IDAT", zlib.compress(b"\x00" * 16)) + chunk(b"IEND", b"")
    return out[:truncate] if truncate else out


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def key_rows(path):
    return sorted(without_measured(r) for r in rows_of(path))


def sweep(scene_path, out, *extra, timeout=300):
    return run(["sweep", scene_path, "--out", out, "--no-report", *extra], timeout=timeout)




def main(classes):
    """Runs the class named on the command line in a temporary folder; exit 1 on failures."""
    table = {f.__name__: f for f in classes}
    if CLASS not in table:
        sys.exit(f"unknown class {CLASS}; one of {', '.join(table)}")
    with tempfile.TemporaryDirectory() as tmp:
        table[CLASS](tmp)
    if failures:
        print("\n".join(failures))
    print(f"{CLASS}: {checks - len(failures)} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)
