#!/usr/bin/python3
"""ctest: broken glTF assets through the real CLI (docs/testing.md "What pgt promises"): the
broken models of Debian's assimp-testmodels, a uri climbing out of the asset's folder, a
device and a folder named as the asset. Each must exit 2 with one stderr line naming the
scene, base.file, the asset and what is wrong, leaving no output behind. Arguments:
PGT_BINARY SOURCE_DIR CLASS."""
import os
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


if __name__ == "__main__":
    main([gltf_assets, gltf_edits])
