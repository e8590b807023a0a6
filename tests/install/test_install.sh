#!/usr/bin/env bash
# Install and package checks (ctest install.*; docs/install.md): `cmake --install` to a
# prefix that is then moved (nothing may depend on where it was built or installed), the
# installed pgt and Python module run from an empty folder with a bare environment, no
# source path in the installed binaries; then `cpack -G DEB`, its dependencies, and the
# .deb's files unpacked into a clean folder run the same way.
# Usage: test_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Runs the installed tree under $1 (holding bin/pgt, share/pgt, lib/python3/dist-packages):
# from an empty folder, with only PATH and HOME set.
check_tree() {
  local root=$1 work=$tmp/work.$RANDOM
  mkdir -p "$work"
  local pgt=$root/bin/pgt share=$root/share/pgt py=$root/lib/python3/dist-packages
  [ -x "$pgt" ] || fail "$pgt missing"
  for f in shaders/presets/godot.glsl analysis/report.py scenes/default.json \
           scenes/maps/stones.png docs/model.md README.md; do
    [ -e "$share/$f" ] || fail "$share/$f missing"
  done
  for bin in "$pgt" "$py"/pgt/_pgt*.so "$root/lib/pgt/pgt_image.so"; do
    if grep -qF "$src" "$bin"; then fail "$bin holds the source path $src"; fi
  done
  local run=(env -i PATH=/usr/bin:/bin HOME="$work")
  # A GLSL scene (shaders from share/pgt) and a small study (its report from share/pgt).
  (cd "$work" && "${run[@]}" "$pgt" render "$share/scenes/glsl_twins.json" --out twins \
      --timing-repeats 1 > render.log) || fail "installed render: $(cat "$work/render.log")"
  [ -f "$work/twins/frame.exr" ] || fail "no frame.exr"
  # Image height maps: a PNG (libpng), and a PGM through this tree's lib/pgt/pgt_image.so.
  (cd "$work" && "${run[@]}" "$pgt" render "$share/scenes/stones_pinhole.json" --out stones \
      --no-timing > stones.log 2>&1) || fail "installed image render: $(cat "$work/stones.log")"
  [ -f "$root/lib/pgt/pgt_image.so" ] || fail "$root/lib/pgt/pgt_image.so missing"
  /usr/bin/python3 - "$share/scenes/stones_pinhole.json" "$work" <<'PY'
import json, sys
scene, work = json.load(open(sys.argv[1])), sys.argv[2]
with open(work + "/ramp.pgm", "wb") as f:
    f.write(b"P5 16 16 255\n" + bytes((x * 16 + y) % 256 for y in range(16) for x in range(16)))
scene["heightmap"] = {"file": "ramp.pgm"}
json.dump(scene, open(work + "/pgm.json", "w"))
PY
  (cd "$work" && "${run[@]}" "$pgt" render pgm.json --out pgm --no-timing > pgm.log 2>&1) ||
    fail "installed render of a PGM map (the image module): $(cat "$work/pgm.log")"
  /usr/bin/python3 - "$share/scenes/default.json" "$work/study.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["methods"] = ["parallax", {"name": "pom", "min_layers": 8, "max_layers": 32},
                    {"preset": "godot"}]
scene["sweep"] = {"theta": [0, 45, 80], "phi": [0], "scale": [0.05], "bias_ratio": [0, -0.5],
                  "resolution": [32, 32], "timing": {"repeats": 1, "fragments": 64,
                                                     "gl_fragments": 4096}}
json.dump(scene, open(sys.argv[2], "w"))
PY
  (cd "$work" && "${run[@]}" "$pgt" sweep study.json --out study > sweep.log) ||
    fail "installed sweep: $(cat "$work/sweep.log")"
  if /usr/bin/python3 -c "import matplotlib, pandas" 2>/dev/null; then
    [ -f "$work/study/report.md" ] || fail "no report: $(cat "$work/sweep.log")"
  fi
  # The module from this tree, not the build's, against the CLI from this tree.
  (cd "$work" && "${run[@]}" PYTHONPATH="$py" /usr/bin/python3 -c \
      "import pgt, sys; assert pgt.__file__.startswith(sys.argv[1]), pgt.__file__" "$py") ||
    fail "import pgt from $py"
  (cd "$work" && "${run[@]}" PYTHONPATH="$py" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m \
      pytest -q -p no:cacheprovider "$src/tests/python/test_module.py" --pgt "$pgt" \
      --scenes "$share/scenes" -k "channels_equal or summary_is or bad_input") ||
    fail "the module's tests against $root"
  echo "ok: $root"
}

echo "== cmake --install, then the prefix moved"
cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log"
mv "$tmp/prefix" "$tmp/moved"
check_tree "$tmp/moved"

echo "== cpack -G DEB, unpacked into a clean folder"
# CPack's own logs say why it failed (its preinstall build, its compression): shown on failure.
cpack_logs() {
  cat "$tmp/cpack.log"
  find "$tmp/deb/_CPack_Packages" -name '*.log' -exec sh -c 'echo "== $1"; tail -n 30 "$1"' _ {} \; 2>/dev/null
  df -h "$tmp" | tail -n 1
}
(cd "$build" && cpack -G DEB -B "$tmp/deb" > "$tmp/cpack.log" 2>&1) || fail "cpack: $(cpack_logs)"
deb=$(ls "$tmp"/deb/pgt_*.deb)
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for p in libembree3 libopenimageio libosdcpu libtbb python3-numpy libegl-mesa0; do
  [[ $depends == *"$p"* ]] || fail "the .deb does not depend on $p"
done
dpkg-deb -x "$deb" "$tmp/root"
check_tree "$tmp/root/usr"
echo "install and package: ok ($deb)"
