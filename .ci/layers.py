#!/usr/bin/python3
"""CI: the folders of src/ include only what lies below them (docs/layout.md, "The data path
and its layers"), and above evaluate/ no file includes the GL path (methods/shader/) itself:
the frame, the commands and the front ends reach it through evaluate/'s headers. Prints
every such #include and exits 1 when there is one."""
import glob
import os
import re
import sys

ORDER = ["core", "io", "heightfield", "mesh", "methods", "scene", "raster", "compare", "truth",
         "evaluate", "frame", "study", "verdict", "cli", "python"]
RANK = {u: i for i, u in enumerate(ORDER)}
SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")


def layer(path):
    return os.path.relpath(path, SRC).split(os.sep)[0]


# Above this layer the GL path is reached only through evaluate/.
GL_DOOR = "evaluate"
upward = []
for path in glob.glob(os.path.join(SRC, "**", "*.[ch]*"), recursive=True):
    if not path.endswith((".h", ".cpp")):
        continue
    for m in re.finditer(r'#include "([^"]+)"', open(path).read()):
        target = os.path.join(SRC, m.group(1))
        if os.path.exists(target) and RANK[layer(target)] > RANK[layer(path)]:
            upward.append(f"{os.path.relpath(path, SRC)} includes {m.group(1)}")
        elif m.group(1).startswith("methods/shader/") and RANK[layer(path)] > RANK[GL_DOOR]:
            upward.append(f"{os.path.relpath(path, SRC)} includes {m.group(1)} (the GL path: "
                          "through evaluate/)")
for line in upward:
    print("layers: upward or GL include:", line)
print(f"layers: {len(upward)} upward or GL includes" + (": FAILED" if upward else ": ok"))
sys.exit(1 if upward else 0)
