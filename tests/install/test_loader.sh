#!/usr/bin/env bash
# OpenImageIO on demand (ctest install.openimageio_on_demand; docs/install.md): the command
# and the Python module do not link libOpenImageIO; a render of a procedural map or of a PNG
# map (read by libpng directly) never loads it; a render of a map in another format (a PGM
# here) loads it from lib/pgt/pgt_image.so beside the binary; a missing
# module named by $PGT_IMAGE_MODULE is an error that names it, and the render writes nothing;
# so is one that is a truncated ELF, a FIFO, a directory, text or a device (exit 2, no hang).
# Usage: test_loader.sh PGT SCENE_DIR [PYTHON_MODULE]
set -euo pipefail
pgt=$1
scenes=$2
module=${3:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# A command that fails under set -e says which, rather than ending the test without a word.
trap 'echo "FAIL: line $LINENO: $BASH_COMMAND (exit $?)" >&2' ERR

for bin in "$pgt" $module; do
  if ldd "$bin" | grep -q 'libOpenImageIO\.so'; then fail "$bin links libOpenImageIO"; fi
done

# Two small views of the default scene: its procedural map, and the bundled stones.png.
/usr/bin/python3 - "$scenes" "$tmp" <<'PY'
import json, sys
scenes, tmp = sys.argv[1], sys.argv[2]
scene = json.load(open(scenes + "/default.json"))
scene["camera"]["resolution"] = [32, 32]
scene["methods"] = ["parallax"]
json.dump(scene, open(tmp + "/procedural.json", "w"))
scene["heightmap"] = {"file": scenes + "/maps/stones.png"}
json.dump(scene, open(tmp + "/png.json", "w"))
# A 16 x 16 8-bit PGM ramp: a format only the image module reads.
with open(tmp + "/ramp.pgm", "wb") as f:
    f.write(b"P5 16 16 255\n" + bytes((x * 16 + y) % 256 for y in range(16) for x in range(16)))
scene["heightmap"] = {"file": tmp + "/ramp.pgm"}
json.dump(scene, open(tmp + "/image.json", "w"))
PY

# LD_DEBUG=files names every object the dynamic loader opens, into LD_DEBUG_OUTPUT.PID (not
# stderr, which pgt captures while a decoder runs).
LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/p.ld "$pgt" render "$tmp/procedural.json" --out "$tmp/p" \
  --no-timing > /dev/null 2> "$tmp/p.log" || fail "procedural render: $(tail -n 5 "$tmp/p.log")"
cat "$tmp"/p.ld.* > "$tmp/p.loaded"
grep -q 'libtbb' "$tmp/p.loaded" || fail "LD_DEBUG listed nothing"
if grep -q 'file=[^ ]*libOpenImageIO\.so' "$tmp/p.loaded"; then
  fail "a render of a procedural map loaded OpenImageIO"
fi
[ -f "$tmp/p/frame.exr" ] && [ -f "$tmp/p/parallax_error.png" ] || fail "no frame.exr or map"

LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/g.ld "$pgt" render "$tmp/png.json" --out "$tmp/g" \
  --no-timing > /dev/null 2> "$tmp/g.log" || fail "PNG render: $(tail -n 5 "$tmp/g.log")"
cat "$tmp"/g.ld.* > "$tmp/g.loaded"
if grep -q 'file=[^ ]*libOpenImageIO\.so' "$tmp/g.loaded"; then
  fail "a render of a PNG map loaded OpenImageIO"
fi
[ -f "$tmp/g/summary.json" ] || fail "no summary.json for the PNG map"

LD_DEBUG=files LD_DEBUG_OUTPUT=$tmp/i.ld "$pgt" render "$tmp/image.json" --out "$tmp/i" \
  --no-timing > /dev/null 2> "$tmp/i.log" || fail "image render: $(tail -n 5 "$tmp/i.log")"
cat "$tmp"/i.ld.* > "$tmp/i.loaded"
grep -q 'file=[^ ]*lib/pgt/pgt_image\.so' "$tmp/i.loaded" || fail "the image module was not loaded"
grep -q 'file=[^ ]*libOpenImageIO\.so' "$tmp/i.loaded" || fail "OpenImageIO was not loaded"
[ -f "$tmp/i/summary.json" ] || fail "no summary.json"

rc=0
PGT_IMAGE_MODULE=$tmp/missing.so "$pgt" render "$tmp/image.json" --out "$tmp/m" --no-timing \
  > "$tmp/m.log" 2>&1 || rc=$?
[ "$rc" -ne 0 ] || fail "a missing image module was not an error"
grep -q 'PGT_IMAGE_MODULE' "$tmp/m.log" || fail "the error does not name PGT_IMAGE_MODULE: $(cat "$tmp/m.log")"
grep -q 'missing.so' "$tmp/m.log" || fail "the error does not name the path: $(cat "$tmp/m.log")"
[ ! -e "$tmp/m/summary.json" ] || fail "a failed render left summary.json"
# Modules that are not a whole shared object for this machine: each exit 2 naming the path,
# within 20 s (a FIFO used to block in open() forever; a truncated ELF, SIGBUS in dlopen).
# libm as the loader resolves it for pgt (ldconfig lives in /sbin, which root's PATH on a CI
# machine may lack).
libm=$(ldd "$pgt" | awk '$1 == "libm.so.6" {print $3; exit}')
[ -n "$libm" ] && [ -f "$libm" ] || fail "ldd $pgt names no libm.so.6"
head -c 4096 "$libm" > "$tmp/truncated.so"
mkfifo "$tmp/fifo.so"
mkdir "$tmp/dir.so"
printf 'not an elf' > "$tmp/text.so"
for bad in "$tmp/truncated.so" "$tmp/fifo.so" "$tmp/dir.so" "$tmp/text.so" /dev/zero; do
  rc=0
  PGT_IMAGE_MODULE=$bad timeout 20 "$pgt" render "$tmp/image.json" --out "$tmp/bad" \
    --no-timing > "$tmp/bad.log" 2>&1 || rc=$?
  [ "$rc" -eq 2 ] || fail "PGT_IMAGE_MODULE=$bad: exit $rc (want 2): $(cat "$tmp/bad.log")"
  grep -q "$bad" "$tmp/bad.log" || fail "the error does not name $bad: $(cat "$tmp/bad.log")"
  [ ! -e "$tmp/bad" ] || fail "PGT_IMAGE_MODULE=$bad left its --out"
done
echo "ok: OpenImageIO on demand"
