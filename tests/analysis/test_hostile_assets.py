#!/usr/bin/python3
"""ctest: broken glTF assets through the real CLI (docs/testing.md "What pgt promises"): the
broken models of Debian's assimp-testmodels, a uri climbing out of the asset's folder, a
device and a folder named as the asset, and hostile assets made here (gltf_hostile: memory,
NULs in uris, required extensions, several primitives). Each must exit 2 with one stderr line
naming the scene, base.file, the asset and what is wrong, leaving no output behind. Arguments:
PGT_BINARY SOURCE_DIR CLASS."""
import array
import base64
import os
import re
import shutil
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hostile_common import *  # noqa: E402,F401,F403  (the harness: run, check, scenes, ...)

MODELS = "/usr/share/assimp/models/glTF2/"
BROKEN = {  # file: what the one line must say
    "IndexOutOfRange/IndexOutOfRange.gltf": "accessor 0 (indices) element 0 is index 255",
    "IndexOutOfRange/AllIndicesOutOfRange.gltf": "is index 65535; the primitive has 24 vertices",
    "BoxBadNormals-glTF-Binary/BoxBadNormals.glb": "accessor 1 (NORMAL) element 0 has length 0",
    "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb": "element 0 is not finite (-inf)",
    "SchemaFailures/sceneWrongType.gltf": "File not found : BoxTextured0.bin",
    "MissingBin/BoxTextured.gltf": "File not found : BoxTextured0.bin",
    "RecursiveNodes/RecursiveNodes.gltf": "is its own ancestor",
    "TestNoRootNode/NoScene.gltf": "the file has no mesh",
    "IncorrectVertexArrays/Cube.gltf": "the primitive has no TEXCOORD_0",
    "draco/2CylinderEngine.gltf": "requires KHR_draco_mesh_compression",
}


def gltf_assets(d):
    """Broken assets: exit 2, one line with the asset and what is wrong; never a crash."""
    def render(base):
        scene = copy(GOOD)
        scene["base"] = base
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        return run(["render", path, "--out", out]), out
    if os.path.isdir(MODELS):
        for rel, what in BROKEN.items():
            r, out = render({"type": "gltf", "file": MODELS + rel})
            expect_error(rel, r, 2, ["scene.json", "base.file", rel, what], out)
        r, out = render({"type": "gltf", "file": MODELS + "IncorrectVertexArrays/Cube.gltf",
                         "mesh": "Lines"})
        expect_error("lines", r, 2, ["has mode 1; pgt reads triangles"], out)
    else:
        check("assimp-testmodels installed", False, MODELS)
    asset = os.path.join(os.path.abspath(SRC), "tests", "data", "gltf", "cylinder.gltf")
    text = open(asset).read()
    os.makedirs(os.path.join(d, "asset"))
    write(d, "secret.bin", "x" * 64)
    write(os.path.join(d, "asset"), "escape.gltf",
          text.replace("\"uri\" : \"data:", "\"uri\" : \"../secret.bin\", \"unused\" : \"data:", 1))
    r, out = render({"type": "gltf", "file": "asset/escape.gltf"})
    expect_error("uri escape", r, 2, ["a uri leaves the asset's folder: ../secret.bin"], out)
    for name, path in [("device", "/dev/zero"), ("folder", d)]:
        r, out = render({"type": "gltf", "file": path})
        expect_error(name, r, 2, ["base.file", "glTF file"], out)
    r, _ = render({"type": "gltf", "file": asset})
    check("the asset itself renders", r.returncode == 0, r.stderr)


def gltf_edits(d):
    """A good asset (Blender's cylinder) edited the ways a hand or a tool breaks one."""
    asset = json.load(open(os.path.join(os.path.abspath(SRC), "tests", "data", "gltf",
                                        "cylinder.gltf")))

    def render(edit, base_extra=None, name="edit.gltf", text=None):
        doc = copy(asset)
        edit(doc)
        write(d, name, text or json.dumps(doc))
        scene = copy(GOOD)
        scene["base"] = {"type": "gltf", "file": name, **(base_extra or {})}
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        return run(["render", path, "--out", out]), out

    deep = json.dumps(asset)[:-1] + ', "extras": ' + "[" * 30000 + "]" * 30000 + "}"
    r, out = render(lambda doc: None, text=deep)
    expect_error("30,000 levels of extras", r, 2, ["base.file", "nested deeper than 64"], out)
    r, out = render(lambda doc: doc["asset"].update(version="1.0"))
    expect_error("glTF 1.0", r, 2, ["asset.version is \"1.0\"; pgt reads glTF 2.0"], out)
    r, out = render(lambda doc: doc.update(extensionsRequired=["EXT_meshopt_compression"]))
    expect_error("meshopt", r, 2, ["requires EXT_meshopt_compression"], out)
    r, out = render(lambda doc: doc["bufferViews"][0].update(byteStride=4))
    expect_error("stride below the element", r, 2, ["byteStride 4, less than"], out)
    r, out = render(lambda doc: None, {"mesh": ""})
    expect_error("empty mesh name", r, 2, ["base.mesh", "an empty name"], out)
    r, out = render(lambda doc: None, {"node": "Cube"})
    expect_error("unknown node name", r, 2, ["base.node", "no node is named \"Cube\""], out)
    r, out = render(lambda doc: None, {"primitive": 2})
    expect_error("primitive out of range", r, 2, ["base.primitive", "primitive 2 of mesh 0"], out)
    # A node by name brings its mesh; without NORMAL the asset's tangents are ignored (glTF).
    r, _ = render(lambda doc: None, {"node": "Cylinder"})
    part = json.load(open(os.path.join(d, "out", "summary.json")))["scene"]["base"]["part"]
    check("node by name", r.returncode == 0 and "node 0" in part, r.stderr + part)
    r, _ = render(lambda doc: doc["meshes"][0]["primitives"][0]["attributes"].pop("NORMAL"))
    frames = json.load(open(os.path.join(d, "out", "summary.json")))["scene"]["base"]["frames"]
    check("no NORMAL: flat normals, MikkTSpace", r.returncode == 0 and frames == "mikktspace",
          r.stderr + frames)


# Runs pgt as the child of a small Python that reports that child's own peak RSS: a child
# forked from this test (holding hundreds of MB of assets) would count the test's memory too.
PEAK = ("import os, sys\n"
        "pid = os.fork()\n"
        "if pid == 0:\n"
        "    os.execv(sys.argv[2], sys.argv[2:])\n"
        "_, status, usage = os.wait4(pid, 0)\n"
        "open(sys.argv[1], 'w').write(str(usage.ru_maxrss))\n"
        "code = os.waitstatus_to_exitcode(status)\n"
        "sys.exit(code if code >= 0 else 128 - code)\n")


def run_peak(args, d, timeout=300):
    """run() that also gives pgt's peak RSS in MB."""
    peak = os.path.join(d, "peak.txt")
    r = subprocess.run(["/usr/bin/python3", "-c", PEAK, peak, PGT] + args, capture_output=True,
                       text=True, timeout=timeout)
    return r, int(open(peak).read()) / 1024


def glb(doc, binary=b""):
    """A .glb: the JSON chunk, then a BIN chunk when `binary` is given."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        binary += b"\0" * (-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def primitive_doc(vertices, corners, indexed=True):
    """One primitive of `vertices` POSITION and TEXCOORD_0 elements and `corners` u32 indices,
    packed in buffer 0 (positions, uvs, indices) of the byteLength they need."""
    views = [(12 * vertices, 34962), (8 * vertices, 34962)]
    views += [(4 * corners, 34963)] if indexed else []
    offsets = [sum(v[0] for v in views[:k]) for k in range(len(views))]
    prim = {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}
    if indexed:
        prim["indices"] = 2
    accessors = [{"bufferView": 0, "componentType": 5126, "count": vertices, "type": "VEC3"},
                 {"bufferView": 1, "componentType": 5126, "count": vertices, "type": "VEC2"},
                 {"bufferView": 2, "componentType": 5125, "count": corners, "type": "SCALAR"}]
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}], "meshes": [{"name": "Grid", "primitives": [prim]}],
            "accessors": accessors[:len(views)],
            "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n, "target": t}
                            for o, (n, t) in zip(offsets, views)],
            "buffers": [{"byteLength": sum(v[0] for v in views)}]}


def grid_bytes(vertices, triangles):
    """Real data for primitive_doc: vertices on a line in x (z, v from the index), the first
    `triangles` triangles unshared (3 vertices each), indexed in order."""
    pos, uv = array.array("f"), array.array("f")
    for k in range(vertices):
        x = (k % 3) * 0.5 + k // 3 * 1e-4
        pos.extend((x, 0.0, 1.0 if k % 3 == 2 else 0.0))
        uv.extend((x, 1.0 if k % 3 == 2 else 0.0))
    return pos.tobytes() + uv.tobytes() + array.array("I", range(3 * triangles)).tobytes()


def gltf_hostile(d):
    """Hostile assets made here: memory estimated from the file's size, its JSON and its
    accessors before a buffer is read or decoded (peak RSS of the refused run under the limit),
    more than 2^24 triangles from the accessor's count, a NUL in a uri, a required extension
    pgt lacks; a mesh of several primitives says which it draws."""
    cylinder = json.load(open(os.path.join(os.path.abspath(SRC), "tests", "data", "gltf",
                                           "cylinder.gltf")))
    # What pgt takes with nothing large to read (its libraries; 145 MB measured): the limit
    # bounds what an input adds to it. A refusal before anything is read adds at most `slack`.
    path = write(d, "plain.json", json.dumps(GOOD))
    r, start = run_peak(["render", path, "--out", os.path.join(d, "plain")], d)
    check("the plain scene renders", r.returncode == 0, r.stderr[:600])
    slack = 16

    def render(name, asset, base_extra=None, limit=None):
        write(d, name, asset if isinstance(asset, (bytes, str)) else json.dumps(asset))
        scene = copy(GOOD)
        scene["base"] = {"type": "gltf", "file": name, **(base_extra or {})}
        path = write(d, "scene.json", json.dumps(scene))
        out = os.path.join(d, "out")
        extra = ["--memory-limit", str(limit)] if limit else []
        r, peak = run_peak(["render", path, "--out", out] + extra, d)
        if r.returncode == 0:
            shutil.rmtree(out)
        return r, out, peak

    def refused(name, asset, limit, words, unread=True):
        r, out, peak = render(name, asset, limit=limit)
        expect_error(name, r, 2, ["scene.json", "base.file", name, "needs about",
                                  f"limit of {limit} MB"] + words, out)
        bound = slack if unread else limit
        check(f"{name}: peak RSS {peak:.0f} MB, {start:.0f} MB at the start + at most {bound}",
              SANITIZED or peak < start + bound)
        return r

    def within_estimate(name, asset, words):
        r = refused(name, asset, 64, words, unread=False)
        need = re.search(r"needs about (\d+) MB", r.stderr)
        if need:
            r, _, peak = render(name, asset, limit=int(need.group(1)))
            check(f"{name} within its estimate of {need.group(1)} MB: exit 0, peak {peak:.0f} MB",
                  r.returncode == 0 and (SANITIZED or peak < start + int(need.group(1))),
                  r.stderr[:600])

    # A 100 MB buffer as a data: URI (133 MB of base64): refused from the file's size, unread.
    big = copy(cylinder)
    n = 104857602  # 100 MB, a multiple of 3: base64 without padding
    big["buffers"].append({"byteLength": n, "uri": "data:application/octet-stream;base64,"})
    text = json.dumps(big).replace("base64,\"", "base64," + "A" * (n // 3 * 4) + "\"", 1)
    refused("data_uri.gltf", text, 100, ["reading a glTF file of 134 MB"])
    # A 30 MB one (40 MB of text) is read, and refused from its JSON before it is parsed.
    n = 31457280
    big["buffers"][1] = {"byteLength": n, "uri": "data:application/octet-stream;base64,"}
    text = json.dumps(big).replace("base64,\"", "base64," + "A" * (n // 3 * 4) + "\"", 1)
    refused("data_uri_30.gltf", text, 100, ["its JSON parsed"], unread=False)
    # A 10 MB one: refused under 64 MB with its whole estimate; accepted under that estimate,
    # and its peak stays within it.
    n = 10485759
    big["buffers"][1] = {"byteLength": n, "uri": "data:application/octet-stream;base64,"}
    text = json.dumps(big).replace("base64,\"", "base64," + "A" * (n // 3 * 4) + "\"", 1)
    within_estimate("data_uri_10.gltf", text, ["buffers 11 MB"])
    del text
    # 20 M vertices and one triangle, declared in a .glb of a few hundred bytes.
    refused("vertices.glb", glb(primitive_doc(20000000, 3)), 200,
            ["20000000 vertices and 1 triangles"])
    # A real 1 M-vertex .glb with one triangle: refused under 64 MB before its buffer is read;
    # under the limit it estimates, accepted, and its peak stays within that estimate.
    within_estimate("million.glb", glb(primitive_doc(1000000, 3), grid_bytes(1000000, 1)),
                    ["1000000 vertices and 1 triangles"])
    # 2^24 + 1 triangles, indexed or not: refused from the accessor's count, nothing read.
    for name, doc, acc in [("triangles.gltf", primitive_doc(3, 3 * (2**24 + 1)), "2 (indices)"),
                           ("soup.glb", glb(primitive_doc(3 * (2**24 + 1), 0, indexed=False)),
                            "0 (POSITION)")]:
        if isinstance(doc, dict):
            doc["buffers"][0]["uri"] = "triangles.bin"  # never read: the count refuses first
        r, out, peak = render(name, doc)
        expect_error(name, r, 2, ["base.file", name, "16777217 triangles (more than 2^24",
                                  f"accessor {acc} has count 50331651"], out)
        check(f"{name}: peak RSS {peak:.0f} MB, {start:.0f} at the start",
              SANITIZED or peak < start + slack)

    # A NUL in a buffer's (or an image's) uri, raw or %00: C would read the path cut there.
    binary = base64.b64decode(cylinder["buffers"][0]["uri"].split(",", 1)[1])
    write(d, "cyl.bin", binary)
    for uri in ["cyl.bin\u0000.txt", "cyl.bin%00.txt"]:
        doc = copy(cylinder)
        doc["buffers"][0]["uri"] = uri  # json.dumps writes the NUL as \u0000
        r, out, _ = render("nul.gltf", doc)
        expect_error(f"uri {uri!r}", r, 2, ["base.file", "nul.gltf", "buffers[0].uri",
                                            "NUL character"], out)
    doc = copy(cylinder)
    doc["images"] = [{"uri": "texture.png\0.txt"}]
    r, out, _ = render("nul_image.gltf", doc)
    expect_error("image uri with a NUL", r, 2, ["images[0].uri", "NUL character"], out)
    doc = copy(cylinder)
    doc["buffers"][0]["uri"] = "cyl.bin"
    r, _, _ = render("bin.gltf", doc)
    check("the same asset with cyl.bin renders", r.returncode == 0, r.stderr[:600])

    # Required extensions pgt lacks are refused by index and name; KHR_mesh_quantization is read.
    for required, k in [(["KHR_texture_transform"], 0),
                        (["KHR_mesh_quantization", "KHR_materials_emissive_strength"], 1),
                        (["EXT_mesh_gpu_instancing"], 0)]:
        doc = copy(cylinder)
        doc["extensionsUsed"] = doc["extensionsRequired"] = required
        r, out, _ = render("required.gltf", doc)
        expect_error(f"requires {required[k]}", r, 2,
                     ["base.file", f"extensionsRequired[{k}] = \"{required[k]}\"",
                      "pgt does not implement"], out)
    doc = copy(cylinder)
    doc["extensionsUsed"] = doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    r, _, _ = render("quantized.gltf", doc)
    check("KHR_mesh_quantization required: renders", r.returncode == 0, r.stderr[:600])

    # Several primitives: one notice naming the mesh, the primitive drawn and how many; none
    # when the scene chose one.
    doc = copy(cylinder)
    doc["meshes"][0]["primitives"] *= 3
    r, _, _ = render("three.gltf", doc)
    notes = [l for l in r.stderr.splitlines() if l.strip()]
    check("three primitives: exit 0 and one notice",
          r.returncode == 0 and len(notes) == 1 and all(
              w in notes[0] for w in ["pgt: note:", "three.gltf", "mesh 0 \"Cylinder\"",
                                      "3 primitives", "primitive 0 is drawn",
                                      "base.primitive"]), r.stderr[:600])
    r, _, _ = render("three.gltf", doc, {"primitive": 2})
    check("primitive chosen: no notice", r.returncode == 0 and r.stderr.strip() == "",
          r.stderr[:600])


if __name__ == "__main__":
    main([gltf_assets, gltf_edits, gltf_hostile])
