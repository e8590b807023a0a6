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
    "TestNoRootNode/NoScene.gltf": "mesh 0 of 0",
    "IncorrectVertexArrays/Cube.gltf": "the primitive has no TEXCOORD_0",
    "draco/2CylinderEngine.gltf": "invalid bufferView",
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


if __name__ == "__main__":
    main([gltf_assets])
